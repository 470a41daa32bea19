#pragma once
// A recognition session on disk, so that a robot can resume: the readings it
// has taken so far (robot frame, as given) and its prior, with the map they
// belong to named by its scene hash. Restoring replays the readings, which
// rebuilds the belief bit for bit (the fold is integer). Layout: the binary
// container (host/io/include/sva/io/binary_file.hpp), magic "SVASESS1", version 2; payload:
//   u64 scene_hash | u32 objects | string scene_name | vector<f64> prior |
//   u32 pose priors (0 or objects) | per object: u8 present [f64 position[3], f64 position_sigma_mm,
//     u8 has_rotation, f64 rotation[9] (column-major), f64 rotation_sigma_rad] |
//   u64 readings | per reading: f64 position[3], normal[3], x_axis[3],
//   u8 status, u16 iterations, f64 time_s, vector<f32> pressure.
// Version 1 held no pose priors and a u32 ground-truth object id in place of the time; it still loads.
#include <sva/prior.hpp>
#include <sva/reading.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace sva::io {

struct SessionFile {
  std::uint64_t scene_hash = 0;
  std::uint32_t objects = 0;
  std::string scene_name;
  Prior prior;  // as the session was given it (checked against the map when restored)
  std::vector<Reading> readings;
};

void save_session_file(const SessionFile& session, const std::filesystem::path& file);
// sva::Error naming the file when it is not a session file, is damaged, or holds a bad reading.
SessionFile load_session_file(const std::filesystem::path& file);

}  // namespace sva::io
