// bench/calibration/calibration_study.sh's sessions: every step's evidence level (calibration/calibration.hpp), as JSON
// lines, for the calibration's two kinds of held-out sessions (as `sva train` runs them) and for sessions on a test set
// with the full map, so that calibration families can be fitted and compared offline
// (bench/calibration/calibration_study.py).
//   calibration_study TRAIN.svad MAP.svam TEST.svad SEED TEST_SESSIONS OUT_PREFIX [KNOWN_SESSIONS [TEST_SEED]]
// writes OUT_PREFIX.objects_held_out.jsonl (the map missing a fifth of the objects: "none of these"),
// OUT_PREFIX.every_object.jsonl (the map of every object: the temperature and the top label) and OUT_PREFIX.test.jsonl
// (TEST_SESSIONS sessions of 30 readings on the test set, the full map). SEED: the map's training seed.
// KNOWN_SESSIONS (default: `sva train`'s 60) sets the known sessions of both calibration maps, so that the fit's noise
// can be measured on disjoint blocks of them (calibration_study.py --blocks); TEST_SEED (default 77) draws other test
// sessions.
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>

#include <cstdio>
#include <fstream>
#include <string>

#include "map/map_builder.hpp"
#include "map/map_file.hpp"
#include "training/calibration_fit.hpp"
#include "training/held_out_sessions.hpp"

using namespace sva;

namespace {

void write_sessions(const std::vector<CalibrationSession>& sessions, const std::string& file) {
  std::ofstream out(file);
  for (const CalibrationSession& s : sessions) {
    out << "{\"known\":" << (s.known ? 1 : 0) << ",\"object\":" << s.object << ",\"steps\":[";
    for (std::size_t i = 0; i < s.steps.size(); ++i) {
      const EvidenceLevel& l = s.steps[i];
      out << (i ? "," : "") << "{\"n\":" << l.readings << ",\"share\":" << l.fit_cost_share << ",\"L\":[";
      for (std::size_t o = 0; o < l.object_log2_mass.size(); ++o) out << (o ? "," : "") << l.object_log2_mass[o];
      out << "],\"G\":[";
      for (std::size_t o = 0; o < l.surface_log2_fit.size(); ++o) out << (o ? "," : "") << l.surface_log2_fit[o];
      out << "]}";
    }
    out << "]}\n";
  }
  if (!out) throw Error("could not write " + file);
  std::fprintf(stderr, "wrote %s (%zu sessions)\n", file.c_str(), sessions.size());
}

// The held-out sessions `sva train` runs on a calibration map of `split`, the fine pose from `fine_pose_from`
// readings (the map's).
std::vector<CalibrationSession> held_out(const Dataset& train, const TrainParameters& params, bool hold_out_objects,
                                         std::size_t known_sessions, std::uint32_t fine_pose_from) {
  const CalibrationOptions co;
  const CalibrationSplit split = split_for_calibration(train, co.held_out_share, params.seed, hold_out_objects);
  HeldOutSessionOptions so = co.sessions;
  so.fine_pose_from = fine_pose_from;
  if (known_sessions > 0) so.known_sessions = known_sessions;
  so.seed = params.seed;
  so.threads = params.threads;
  if (!hold_out_objects) so.unknown_sessions = 0;
  return run_held_out_sessions(*train_pair_map(split.map_part, params, nullptr), split, so);
}

// A count or seed from the command line, or an error naming the argument.
std::uint64_t whole_number(const char* what, const std::string& text) {
  std::size_t used = 0;
  unsigned long long v = 0;
  try {
    v = std::stoull(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || text[0] == '-')
    throw Error(std::string(what) + " '" + text + "' is not a whole number");
  return v;
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 7 || argc > 9) {
    std::fprintf(stderr,
                 "usage: calibration_study TRAIN.svad MAP.svam TEST.svad SEED TEST_SESSIONS OUT_PREFIX "
                 "[KNOWN_SESSIONS [TEST_SEED]]\n");
    return 2;
  }
  // Every number first, so that a mistyped one is refused before minutes of sessions.
  TrainOptions to;
  to.seed = whole_number("SEED", argv[4]);
  HeldOutSessionOptions so;  // the test sessions
  so.known_sessions = whole_number("TEST_SESSIONS", argv[5]);
  so.unknown_sessions = 0;
  so.readings = 30;
  so.seed = argc > 8 ? whole_number("TEST_SEED", argv[8]) : 77;  // not the training seed: other poses and orders
  const std::size_t known = argc > 7 ? whole_number("KNOWN_SESSIONS", argv[7]) : 0;
  const Dataset train = load_dataset(argv[1]);
  const TrainParameters params = resolve_train_parameters(train.scene, to);
  const std::string out = argv[6];
  const auto map = load_pair_map(argv[2]);
  so.fine_pose_from = map->calibration.fine_pose_from;
  write_sessions(held_out(train, params, true, known, so.fine_pose_from), out + ".objects_held_out.jsonl");
  write_sessions(held_out(train, params, false, known, so.fine_pose_from), out + ".every_object.jsonl");
  CalibrationSplit test;  // every test reading "held out", every object known
  test.held_out = load_dataset(argv[3]);
  for (std::size_t o = 0; o < test.held_out.scene.objects.size(); ++o)
    test.map_object.push_back(static_cast<std::int32_t>(o));
  write_sessions(run_held_out_sessions(*map, test, so), out + ".test.jsonl");
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "calibration_study: %s\n", e.what());
  return 1;
}
