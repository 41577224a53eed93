// The options a command's --help text defines, read from the text itself: its option lines
// ("  -o, --output OUT.exr   the image") and its "Usage:" line ("[--scene INDEX]"). A command whose
// options are written only in its help and its parser takes its lists from here (the flags for
// split_option_value, the names for did_you_mean), and `dacrt completion` and `dacrt man` read
// every command's help so.
#pragma once

#include <string>
#include <vector>

namespace dacrt {

// An option a help text defines, with its short name and each value it is shown with ("OUT.exr";
// one per line for an option on several lines: "rays", "triangles"); a flag has none.
struct HelpOption {
  std::string name, short_name;
  std::vector<std::string> values;
};
std::vector<HelpOption> help_options(const std::string& help);

// The long names of the options `help` defines ("--output"), for did_you_mean.
std::vector<std::string> help_option_names(const std::string& help);
// Those of its flags, the options shown without a value ("--quiet"), for split_option_value.
std::vector<std::string> help_flag_names(const std::string& help);

// The pieces the reading is made of, for other readers of help texts: the lines of a text, its
// words, whether a word is an option ("-o", "--spp"), an item's column (the text of a line from
// `at` up to two spaces: "--spp N" of "  --spp N   samples"), and an option added to a list (or its
// value to the option already there).
std::vector<std::string> text_lines(const std::string& text);
std::vector<std::string> text_words(const std::string& text);
bool is_option_word(const std::string& word);
std::string item_column(const std::string& line, size_t at);
void add_help_option(std::vector<HelpOption>& options, const std::string& name,
                     const std::string& short_name, const std::string& value);

}  // namespace dacrt
