// `dacrt merge PART.exr... -o OUT.exr`: adds the parts of one render (`render --samples
// FIRST:LAST`, each keeping its exact sums) into the image of their union, bit for bit the image
// one render of those samples makes. Parts of different renders, parts that share samples and,
// unless --allow-gaps, parts that leave samples out are refused with one line naming the files.
#pragma once

#include <string>
#include <vector>

namespace dacrt {

// The command's exit code (0); throws UsageError or Error.
int merge_main(const std::vector<std::string>& args);

}  // namespace dacrt
