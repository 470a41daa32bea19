#include <sva/io/json.hpp>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

namespace sva::io {

std::optional<int> json_int(const nlohmann::json& v, int lo, int hi) {
  if (!v.is_number()) return std::nullopt;
  const double d = v.get<double>();
  if (!(d >= lo && d <= hi) || d != std::floor(d)) return std::nullopt;
  return static_cast<int>(d);
}

std::optional<float> json_float(const nlohmann::json& v) {
  if (!v.is_number()) return std::nullopt;
  const double d = v.get<double>();
  if (!std::isfinite(d) || std::fabs(d) > std::numeric_limits<float>::max()) return std::nullopt;
  return static_cast<float>(d);
}

nlohmann::json parse_json(std::string_view text) { return nlohmann::json::parse(text); }

std::string dump_json(const nlohmann::json& v, int indent, bool replace_invalid_utf8) {
  return v.dump(
      indent, ' ', false,
      replace_invalid_utf8 ? nlohmann::json::error_handler_t::replace : nlohmann::json::error_handler_t::strict);
}

}  // namespace sva::io
