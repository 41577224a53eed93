// `dacrt convert IN.exr OUT.EXT`: an EXR (a render's, or any RGB EXR) written in the format OUT's
// name says, through the same writer as render's outputs (io/image_file.h): a render's EXR
// converted with render's --view and --exposure gives the bytes its --preview gave.
#pragma once

#include <string>
#include <vector>

namespace dacrt {

// The command's exit code (0); throws UsageError or Error.
int convert_main(const std::vector<std::string>& args);

}  // namespace dacrt
