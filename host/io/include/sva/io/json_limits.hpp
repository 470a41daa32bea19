#pragma once
// Limits on JSON read from outside (scenes, calibrations, batch sessions, recordings' settings, glTF). Parsing is
// iterative, but printing a value (json::dump, used in error messages and to hand a block on) and tinygltf's
// reading of "extras" recurse once per level: a file of 100,000 nested brackets would overflow the stack. No sva
// format nests deeper than a few levels, so anything past kMaxJsonDepth is refused before parsing.
#include <cmath>
#include <cstddef>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
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
inline std::optional<int> json_int(const nlohmann::json& v, int lo, int hi) {
  if (!v.is_number()) return std::nullopt;
  const double d = v.get<double>();
  if (!(d >= lo && d <= hi) || d != std::floor(d)) return std::nullopt;
  return static_cast<int>(d);
}
// `v` as a float; nullopt when it is not a finite number within float's range.
inline std::optional<float> json_float(const nlohmann::json& v) {
  if (!v.is_number()) return std::nullopt;
  const double d = v.get<double>();
  if (!std::isfinite(d) || std::fabs(d) > std::numeric_limits<float>::max()) return std::nullopt;
  return static_cast<float>(d);
}

}  // namespace sva::io
