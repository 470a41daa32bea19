#include <sva/eval/dataset_export.hpp>

#include <cstdio>
#include <ostream>

#include <sva/io/text_file.hpp>
#include "plot/canvas.hpp"

namespace sva::io {

namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace

void write_dataset_csv(const Dataset& d, const std::filesystem::path& file) {
  const auto elements = static_cast<std::size_t>(d.scene.sensor.elements());
  write_file_atomically(file, [&](std::ostream& out) {
    out << "object,object_name,status,iterations,px,py,pz,nx,ny,nz,xx,xy,xz";
    for (int i = 0; i < d.scene.sensor.rows; ++i)
      for (int j = 0; j < d.scene.sensor.cols; ++j) out << ",p_r" << i << "c" << j;
    out << "\n";
    for (const auto& s : d.samples) {
      const Reading& r = s.reading;
      out << s.object << "," << csv_field(d.scene.objects[s.object].name) << "," << to_string(r.status) << ","
          << r.iterations;
      for (const auto* v : {&r.position, &r.normal, &r.x_axis})
        out << "," << number(v->x) << "," << number(v->y) << "," << number(v->z);
      for (std::size_t k = 0; k < elements; ++k) out << "," << number(r.pressure[k]);
      out << "\n";
    }
  });
}

std::size_t write_dataset_ply(const Dataset& d, const std::string& source, const std::filesystem::path& file) {
  std::size_t points = 0;
  for (const auto& s : d.samples) points += s.reading.status != ControllerStatus::no_contact;
  write_file_atomically(file, [&](std::ostream& out) {
    out << "ply\nformat ascii 1.0\ncomment sva dataset " << source << " (" << d.split << "), scene " << d.scene.name
        << "\ncomment contact points with outward normals, coloured by object\nelement vertex " << points
        << "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty "
           "float nz\n"
           "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uint object\nend_header\n";
    char buf[256];
    for (const auto& s : d.samples) {
      const Reading& r = s.reading;
      if (r.status == ControllerStatus::no_contact) continue;
      const plot::Rgb c = plot::palette(s.object);
      std::snprintf(buf, sizeof buf, "%.6f %.6f %.6f %.6f %.6f %.6f %d %d %d %u\n", r.position.x, r.position.y,
                    r.position.z, r.normal.x, r.normal.y, r.normal.z, c.r, c.g, c.b, s.object);
      out << buf;
    }
  });
  return points;
}

}  // namespace sva::io
