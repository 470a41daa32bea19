#pragma once
// JSON in sva: the limits on what is read from outside, the range checks, and the one compiled parser and
// printer.
// Limits on JSON read from outside (scenes, calibrations, batch sessions, recordings' settings, glTF). Parsing is
// iterative, but printing a value (json::dump, used in error messages and to hand a block on) and tinygltf's
// reading of "extras" recurse once per level: a file of 100,000 nested brackets would overflow the stack. No sva
// format nests deeper than a few levels, so anything past kMaxJsonDepth is refused before parsing.
#include <cstddef>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace sva::io {

inline constexpr std::size_t kMaxJsonDepth = 64;

// The deepest nesting of arrays and objects in `text`; brackets inside strings do not count. Stops counting at
// kMaxJsonDepth + 1.
inline std::size_t json_depth(std::string_view text) {
  std::size_t depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (char c : text) {
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > deepest && (deepest = depth) > kMaxJsonDepth) break;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

// The message for a document nested too deeply, after "FILE: ".
inline const char* json_too_deep_message() { return "JSON nested deeper than 64 levels (arrays or objects)"; }

// Numbers read into narrower C++ types: nlohmann's get<int>() and get<float>() convert 1e300 with undefined
// behaviour and 2^40 to a wrapped value, so a field is range-checked as a double first.
// `v` as an integer in [lo, hi]; nullopt when it is not a whole number in that range.
std::optional<int> json_int(const nlohmann::json& v, int lo, int hi);
// `v` as a float; nullopt when it is not a finite number within float's range.
std::optional<float> json_float(const nlohmann::json& v);

// nlohmann's parser and printer, compiled once here (host/io/src/json.cpp): instantiated in each file that reads
// or writes JSON they cost about 3 s of that file's compile, and some twenty files do (the first command's build).
// A file that works on values includes <nlohmann/json.hpp> itself; one that only passes them on needs this header.
// `text` parsed; throws nlohmann::json::parse_error (a nlohmann::json::exception) as json::parse does. The caller
// checks json_depth first where the text comes from outside.
nlohmann::json parse_json(std::string_view text);
// `v` printed (indent < 0: on one line). Invalid UTF-8 in a string throws nlohmann::json::type_error, unless
// `replace_invalid_utf8`, which writes U+FFFD for it (a page shows what it can of a name rather than nothing).
std::string dump_json(const nlohmann::json& v, int indent = -1, bool replace_invalid_utf8 = false);

}  // namespace sva::io
