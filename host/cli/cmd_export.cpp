// sva export: a dataset as CSV (one row per reading) and PLY (contact points
// with normals, coloured by object), for other tools; or, with --recording, as
// a sensor session recording (frames, poses) that `sva replay` plays.
#include <unistd.h>
#include <sva/dataset.hpp>
#include <sva/drivers/session.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "args.hpp"
#include "io/text_file.hpp"
#include "plot/canvas.hpp"

namespace sva::cli {

namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

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
  const int elements = d.scene.sensor.elements();

  io::write_file_atomically(csv, [&](std::ostream& out) {
    out << "object,object_name,status,iterations,px,py,pz,nx,ny,nz,xx,xy,xz";
    for (int i = 0; i < d.scene.sensor.rows; ++i)
      for (int j = 0; j < d.scene.sensor.cols; ++j) out << ",p_r" << i << "c" << j;
    out << "\n";
    char buf[64];
    auto num = [&](double v) {
      std::snprintf(buf, sizeof buf, "%.9g", v);
      return std::string(buf);
    };
    for (const auto& s : d.samples) {
      const Reading& r = s.reading;
      out << s.object << "," << csv_field(d.scene.objects[s.object].name) << "," << to_string(r.status) << ","
          << r.iterations;
      for (const auto* v : {&r.position, &r.normal, &r.x_axis})
        out << "," << num(v->x) << "," << num(v->y) << "," << num(v->z);
      for (int k = 0; k < elements; ++k) out << "," << num(r.pressure[static_cast<std::size_t>(k)]);
      out << "\n";
    }
  });

  std::size_t points = 0;
  for (const auto& s : d.samples) points += s.reading.status != ControllerStatus::no_contact;
  io::write_file_atomically(ply, [&](std::ostream& out) {
    out << "ply\nformat ascii 1.0\ncomment sva dataset " << file.filename().string() << " (" << d.split << "), scene "
        << d.scene.name << "\ncomment contact points with outward normals, coloured by object\nelement vertex "
        << points
        << "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty "
           "float nz\n"
           "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uint object\nend_header\n";
    char buf[256];
    for (const auto& s : d.samples) {
      const Reading& r = s.reading;
      if (r.status == ControllerStatus::no_contact) continue;
      plot::Rgb c = plot::palette(s.object);
      std::snprintf(buf, sizeof buf, "%.6f %.6f %.6f %.6f %.6f %.6f %d %d %d %u\n", r.position.x, r.position.y,
                    r.position.z, r.normal.x, r.normal.y, r.normal.z, c.r, c.g, c.b, s.object);
      out << buf;
    }
  });
  std::printf("wrote %s (%zu readings) and %s (%zu contact points)\n", csv.c_str(), d.samples.size(), ply.c_str(),
              points);
  return 0;
}

}  // namespace sva::cli
