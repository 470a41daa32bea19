#include "recognition/session_file.hpp"

#include <sva/error.hpp>
#include <sva/io/binary_file.hpp>

#include <cmath>
#include <string_view>

namespace sva::io {

namespace {
constexpr std::string_view kMagic = "SVASESS1";
constexpr std::uint32_t kVersion = 2;  // 2: a reading stores its time (1: a ground-truth object id)
constexpr std::uint32_t kOldestVersion = 1;
constexpr std::size_t kMaxElements = 1 << 16;  // pressure values of one reading
// The fewest bytes a reading takes (9 f64, u8, u16, the version-1 u32 object id or the version-2 f64 time, an empty
// pressure vector's u64 length): the count is checked against them before the readings are allocated.
constexpr std::size_t min_reading_bytes(std::uint32_t version) { return 9 * 8 + 1 + 2 + (version >= 2 ? 8 : 4) + 8; }

void put_pose_priors(BinaryWriter& w, const std::vector<std::optional<PosePrior>>& priors) {
  w.put(static_cast<std::uint32_t>(priors.size()));
  for (const auto& p : priors) {
    w.put(static_cast<std::uint8_t>(p.has_value()));
    if (!p) continue;
    w.put_array(&p->position.x, 3);
    w.put(p->position_sigma_mm);
    w.put(static_cast<std::uint8_t>(p->has_rotation));
    w.put_array(&p->rotation[0][0], 9);
    w.put(p->rotation_sigma_rad);
  }
}

// Values are checked against the map (finite, positive sigmas, a rotation) when the session is restored.
std::vector<std::optional<PosePrior>> get_pose_priors(BinaryReader& r, std::uint32_t objects) {
  const auto n = r.get<std::uint32_t>();
  if (n != 0 && n != objects)
    r.fail(std::to_string(n) + " pose priors for " + std::to_string(objects) + " objects (0 or one per object)");
  if (n > r.remaining()) r.fail(std::to_string(n) + " pose priors exceed the file");  // a flag byte each, at least
  std::vector<std::optional<PosePrior>> out(n);
  for (auto& p : out) {
    const auto present = r.get<std::uint8_t>();
    if (present > 1) r.fail("pose prior flag " + std::to_string(present) + " is not 0 or 1");
    if (!present) continue;
    p.emplace();
    r.get_array(&p->position.x, 3);
    p->position_sigma_mm = r.get<double>();
    const auto rot = r.get<std::uint8_t>();
    if (rot > 1) r.fail("pose prior rotation flag " + std::to_string(rot) + " is not 0 or 1");
    p->has_rotation = rot == 1;
    r.get_array(&p->rotation[0][0], 9);
    p->rotation_sigma_rad = r.get<double>();
  }
  return out;
}

// Saving refuses what loading would refuse: a missing folder is a typo in the path far more often than a wish to
// create it, and the clear error beats a rename's.
void check_session_target(const std::filesystem::path& file) {
  if (file.empty()) throw Error("save_session: the file name is empty");
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    throw Error(file.string() + ": is a folder, expected a session file name");
  const auto folder = file.parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
    throw Error(file.string() + ": cannot save: the folder " + folder.string() +
                (std::filesystem::exists(folder, ec) ? " is not a folder" : " does not exist"));
}

}  // namespace

void save_session_file(const SessionFile& session, const std::filesystem::path& file) {
  check_session_target(file);
  BinaryWriter w;
  w.put(session.scene_hash);
  w.put(session.objects);
  w.put_string(session.scene_name);
  w.put_vector(session.prior.object_probability);
  put_pose_priors(w, session.prior.object_pose);
  w.put<std::uint64_t>(session.readings.size());
  for (const Reading& r : session.readings) {
    for (const glm::dvec3& v : {r.position, r.normal, r.x_axis}) w.put_array(&v.x, 3);
    w.put(static_cast<std::uint8_t>(r.status));
    w.put(r.iterations);
    w.put(r.time_s);
    w.put_vector(r.pressure);
  }
  w.write_file(file, kMagic, kVersion);
}

SessionFile load_session_file(const std::filesystem::path& file) {
  BinaryReader r(file, kMagic, kOldestVersion, kVersion, "session");
  SessionFile s;
  s.scene_hash = r.get<std::uint64_t>();
  s.objects = r.get<std::uint32_t>();
  s.scene_name = r.get_string();
  s.prior.object_probability = r.get_vector<double>(s.objects);
  if (r.version() >= 2) s.prior.object_pose = get_pose_priors(r, s.objects);
  const auto n = r.get<std::uint64_t>();
  if (n > r.remaining() / min_reading_bytes(r.version())) r.fail(std::to_string(n) + " readings exceed the file");
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
    if (r.version() >= 2) {
      x.time_s = r.get<double>();
      if (!std::isfinite(x.time_s)) r.fail("reading time is not finite");
    } else {
      r.get<std::uint32_t>();  // version 1 kept the dataset's object id, which recognition never read
    }
    x.pressure = r.get_vector<float>(kMaxElements);
  }
  r.expect_end();
  return s;
}

}  // namespace sva::io
