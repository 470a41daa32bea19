#pragma once
// The JSON lines the sensor commands print: a reading as it forms, and the
// estimate after it (the same output from sva replay and sva record --map).
#include <sva/drivers/contact_readings.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>

#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>

namespace sva::cli {

nlohmann::json reading_json(const drivers::FormedReading& reading);
nlohmann::json estimate_json(const Estimate& estimate, double time);

// Prints each reading as it forms and, with a map, recognises the converged ones
// and prints the estimate after each (stdout), with a one-line summary on stderr.
class ReadingPrinter {
 public:
  // map_file "" : print readings only.
  ReadingPrinter(const std::string& command, const std::string& map_file, BackendKind backend);
  void operator()(const drivers::FormedReading& reading);
  std::size_t readings() const { return readings_; }
  std::size_t recognised() const { return recognised_; }
  double worst_update_ms() const { return worst_update_ms_; }

 private:
  std::string command_;
  std::optional<Map> map_;
  std::optional<Recognizer> recognizer_;
  std::size_t readings_ = 0, recognised_ = 0;
  double worst_update_ms_ = 0;
};

}  // namespace sva::cli
