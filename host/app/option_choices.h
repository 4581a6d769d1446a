// Options whose value is one of a few names (--aa adaptive|none|uniform, ...): one table of
// name -> enum per option, so parsing, validation, the --help text and the names written
// to --stats all come from the same place. CLI11 rejects any other name while parsing the
// command line, before a scene is loaded.
#pragma once

#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>

namespace zz {

template <class E>
struct Choice {
  const char* name;
  E value;
};

template <class E, size_t N>
const char* name_of(const Choice<E> (&choices)[N], E value) {
  for (const Choice<E>& c : choices)
    if (c.value == value) return c.name;
  return "?";
}

template <class E, size_t N>
std::string choice_names(const Choice<E> (&choices)[N]) {
  std::string names;
  for (const Choice<E>& c : choices) names += (names.empty() ? "" : "|") + std::string(c.name);
  return names;
}

// Registers `--flag NAME` storing the enum in `value`; the help text gets the names and
// the default (the value `value` holds now).
template <class E, size_t N>
CLI::Option* add_choice(CLI::App* cmd, const std::string& flag, E& value, const Choice<E> (&choices)[N],
                        const std::string& help) {
  // Name -> the enum's number, which CLI11 then stores in `value`.
  CLI::Validator to_enum(
      [&choices](std::string& text) -> std::string {
        for (const Choice<E>& c : choices)
          if (text == c.name) {
            text = std::to_string(static_cast<long long>(c.value));
            return "";
          }
        return "'" + text + "' is not one of " + choice_names(choices);
      },
      "");
  return cmd->add_option(flag, value, help + " (default " + std::string(name_of(choices, value)) + ")")
      ->transform(to_enum)
      ->type_name(choice_names(choices));
}

}  // namespace zz
