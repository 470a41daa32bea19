#include "io/session_file.hpp"

#include <sva/error.hpp>

#include "io/binary_file.hpp"

#include <string_view>

namespace sva::io {

namespace {
constexpr std::string_view kMagic = "SVASESS1";
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kMaxElements = 1 << 16;  // pressure values of one reading
// The fewest bytes a reading takes (9 f64, u8, u16, u32, an empty pressure vector's u64 length): the count is
// checked against them before the readings are allocated.
constexpr std::size_t kMinReadingBytes = 9 * 8 + 1 + 2 + 4 + 8;
}  // namespace

void save_session_file(const SessionFile& session, const std::filesystem::path& file) {
  BinaryWriter w;
  w.put(session.scene_hash);
  w.put(session.objects);
  w.put_string(session.scene_name);
  w.put_vector(session.prior);
  w.put<std::uint64_t>(session.readings.size());
  for (const Reading& r : session.readings) {
    for (const glm::dvec3& v : {r.position, r.normal, r.x_axis}) w.put_array(&v.x, 3);
    w.put(static_cast<std::uint8_t>(r.status));
    w.put(r.iterations);
    w.put(r.object);
    w.put_vector(r.pressure);
  }
  w.write_file(file, kMagic, kVersion);
}

SessionFile load_session_file(const std::filesystem::path& file) {
  BinaryReader r(file, kMagic, kVersion, "session");
  SessionFile s;
  s.scene_hash = r.get<std::uint64_t>();
  s.objects = r.get<std::uint32_t>();
  s.scene_name = r.get_string();
  s.prior = r.get_vector<double>(s.objects);
  const auto n = r.get<std::uint64_t>();
  if (n > r.remaining() / kMinReadingBytes) r.fail(std::to_string(n) + " readings exceed the file");
  s.readings.resize(n);
  for (Reading& x : s.readings) {
    r.get_array(&x.position.x, 3);
    r.get_array(&x.normal.x, 3);
    r.get_array(&x.x_axis.x, 3);
    const auto status = r.get<std::uint8_t>();
    if (status > static_cast<std::uint8_t>(ControllerStatus::no_contact))
      r.fail("reading status " + std::to_string(status) + " is not a controller status");
    x.status = static_cast<ControllerStatus>(status);
    x.iterations = r.get<std::uint16_t>();
    x.object = r.get<std::uint32_t>();
    x.pressure = r.get_vector<float>(kMaxElements);
  }
  r.expect_end();
  return s;
}

}  // namespace sva::io
