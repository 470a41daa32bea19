// sva export: a dataset as CSV (one row per reading) and PLY (contact points
// with normals, coloured by object), for other tools; or, with --recording, as
// a sensor session recording (frames, poses) that `sva replay` plays.
#include <unistd.h>
#include <sva/dataset.hpp>
#include <sva/drivers/session.hpp>
#include <sva/eval/dataset_export.hpp>

#include <algorithm>
#include <cstdio>

#include "args.hpp"

namespace sva::cli {

int cmd_export(const std::vector<std::string>& argv) {
  Args a("sva export",
         "Write a dataset as CSV (one row per reading: object, status, iterations, position, normal, x axis,\n"
         "pressures) and PLY (contact points with normals, coloured by object) into DIR. With --recording,\n"
         "write it as a sensor session recording instead: frames encoded from the pressure images (0.01 kPa per\n"
         "count), the sensor poses as the arm's pose stream, one touch per reading at --touch-rate.",
         argv);
  a.option("--data", "FILE", "a dataset file (.svad) from sva simulate")
      .option("--out", "DIR", "output directory (created if needed)")
      .option("--recording", "SESSION", "write a session recording (for sva replay) instead of CSV and PLY")
      .option("--touch-rate", "HZ", "touches per second in the recording (default 2)")
      .option("--frame-rate", "HZ", "sensor frames per second in the recording (default 100)");
  if (!a.parse()) return 0;
  const std::filesystem::path file = a.required("--data");
  Dataset d = load_dataset(file);
  if (auto session = a.get("--recording")) {
    const double touch = a.number("--touch-rate", 2.0, 1e-3, 1e3), frames = a.number("--frame-rate", 100.0, 1.0, 1e5);
    drivers::export_dataset_session(d, drivers::export_calibration(d.scene.sensor), touch, frames, *session);
    std::printf(
        "wrote %s (%zu readings with contact as touches at %g Hz, frames at %g Hz)\n", session->c_str(),
        d.samples.size() - static_cast<std::size_t>(std::count_if(
                               d.samples.begin(), d.samples.end(),
                               [](const Sample& s) { return s.reading.status == ControllerStatus::no_contact; })),
        touch, frames);
    return 0;
  }
  const std::filesystem::path dir = a.required("--out");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir, ec)) throw Error(dir.string() + ": cannot create output directory");
  const std::string stem = file.stem().string();
  const auto csv = dir / (stem + ".csv"), ply = dir / (stem + ".ply");
  io::write_dataset_csv(d, csv);
  const std::size_t points = io::write_dataset_ply(d, file.filename().string(), ply);
  std::printf("wrote %s (%zu readings) and %s (%zu contact points)\n", csv.c_str(), d.samples.size(), ply.c_str(),
              points);
  return 0;
}

}  // namespace sva::cli
