// `dacrt completion bash` and `dacrt man`: the bash completion script and the manual page dacrt(1),
// both made from what the commands print for --help (one text per command, the one source of its
// options) and, for the render options, from the option table (render/render_option_table.cpp:
// each option's value type and its known values).
#pragma once

#include <string>
#include <vector>

#include "dacrt/util/help_text.h"

namespace dacrt {

// A command of the CLI and its --help text, as it prints it.
struct CommandHelp {
  std::string name, help;
};

// The bash completion script (`source <(dacrt completion bash)`): the commands, each command's
// options, the values the option table knows (--backend, --integrator, --sampler, --aov, ...),
// the display views of --view (asked of `dacrt views` when completed, so $OCIO's), and file names
// filtered by the extension the help shows (SCENE: .gltf and .glb; OUT.exr: .exr; DIR: folders).
std::string bash_completion(const std::vector<CommandHelp>& commands);

// The manual page dacrt(1), in roff with the man macros: `main_help` (the command list), then a
// section per command made of its --help.
std::string man_page(const std::string& main_help, const std::vector<CommandHelp>& commands,
                     const std::string& version);

}  // namespace dacrt
