#pragma once
// One formatted cell of a printed table: a value, or "-" when there is none
// (e.g. no trial had the right object). Shared by eval's report and the
// robustness sweep's table.
#include <cstdio>
#include <optional>
#include <string>

namespace sva::eval {

inline std::string cell(const std::optional<double>& v, const char* format) {
  if (!v) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, *v);
  return buf;
}

}  // namespace sva::eval
