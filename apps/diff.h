// `dacrt diff A.exr B.exr`: how far one image is from another. Compares the RGB channels of two
// OpenEXR images of the same size in linear values, B the reference, and prints RMSE, relMSE,
// MAE, SMAPE and the largest difference per channel and over all three; optionally writes the
// per-pixel error as an EXR and as a false-colour PNG with a labelled colour bar.
#pragma once

#include <string>
#include <vector>

namespace dacrt {

// The command's exit code (0); throws UsageError or Error.
int diff_main(const std::vector<std::string>& args);

}  // namespace dacrt
