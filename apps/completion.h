// `dacrt completion bash` and `dacrt man`: the bash completion script and the manual page dacrt(1),
// both made from what the commands print for --help (one text per command, the one source of its
// options) and, for the render options, from the option table (render/render_option_table.cpp:
// each option's value type and its known values).
#pragma once

#include <string>
#include <vector>

namespace dacrt {

// A command of the CLI and its --help text, as it prints it.
struct CommandHelp {
  std::string name, help;
};

// An option a help text defines: on an option line ("  -o, --output OUT.exr   the image") or in
// its "Usage:" line ("[--scene INDEX]"), with its short name and each value it is shown with
// ("OUT.exr"; one per line for an option on several lines: "rays", "triangles"); a flag has none.
struct HelpOption {
  std::string name, short_name;
  std::vector<std::string> values;
};
std::vector<HelpOption> help_options(const std::string& help);

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
