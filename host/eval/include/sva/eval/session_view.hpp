#pragma once
// A session in the browser (sva view, docs/view.md): the readings replayed through a recognizer one by one, each
// step's estimate (object probabilities, "none of these", the distinct hypotheses with their poses) and, where
// the truth is known, its errors; the objects' meshes as vertex arrays; all of it written into one self-contained
// HTML page with three.js (Debian's libjs-three) and the viewer (assets/view) inlined, which works offline.
#include <sva/map.hpp>
#include <sva/pose.hpp>
#include <sva/reading.hpp>
#include <sva/recognizer.hpp>
#include <sva/scene.hpp>

#include <cstdint>
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <span>
#include <string>

namespace sva::view {

struct SessionTruth {
  std::uint32_t object = 0;  // the map's object id
  RigidPose pose;            // the object's true pose (robot frame)
};

struct SessionViewSpec {
  std::string title;   // the page's title (e.g. "paper3d trial 4")
  std::string source;  // where the readings came from (a dataset and trial, a sessions file and session)
  std::string map_name;
  RecognizerOptions options;  // the recognizer's (backend, fine pose, ...), as the run being looked at used them
  std::size_t top_k = 5;      // hypotheses per step
  bool progress = false;      // report the replay's progress on stderr (a long session takes minutes)
};

// Replays `readings` and returns the page's data (docs/view.md, "The data"). `scene` gives the meshes of the truth
// and of every hypothesis' object (none where it is null), and the symmetries the errors respect.
nlohmann::json session_view_data(const Map& map, const Scene* scene, std::span<const Reading> readings,
                                 const std::optional<SessionTruth>& truth, const SessionViewSpec& spec);

// Writes the page: assets/view/viewer.html with three.js (SVA_THREE_JS or /usr/share/javascript/three), its orbit
// controls and assets/view/viewer.js inlined, and `data`. Atomic; sva::Error names a missing file or package.
void write_session_page(const std::filesystem::path& out, const nlohmann::json& data);

}  // namespace sva::view

namespace sva::eval {
struct EvalOptions;
struct EvalResult;
struct Curve;
}  // namespace sva::eval
namespace sva {
struct Dataset;
}

namespace sva::eval {
class TrialGenerator;
}

namespace sva::view {

// Evaluation trial `t` as a session to show, as `sva eval` makes it (`generator` from `data_name` with `seed`):
// its readings, its truth where the map holds the object, and the page's title and source.
struct TrialView {
  std::vector<Reading> readings;
  std::optional<SessionTruth> truth;
  std::string title, source;
};
TrialView trial_view(const Map& map, const Dataset& test, const eval::TrialGenerator& generator, std::size_t t,
                     std::uint64_t seed, const std::string& data_name);

// `sva eval --html DIR`: one page per trial of a random-policy evaluation (its trials made again from the same seed:
// each trial is replayed once more), the accuracy figure, and an index page with the worst trials first (wrong at
// the end, then the lowest probability of the truth, then the largest translation error) and links to every page.
// Returns the number of pages written.
std::size_t write_trial_pages(const std::filesystem::path& dir, const Map& map, const Dataset& test,
                              const eval::EvalOptions& options, const eval::EvalResult& result,
                              const eval::Curve& curve);

}  // namespace sva::view
