// sva recognize: batch recognition of many independent sessions (docs/batch-format.md).
// Sessions are stepped together, so each update of the backend (one GPU
// submission with --backend vulkan) carries one reading of every session.
#include <sva/batch_file.hpp>
#include <sva/batch_recognizer.hpp>
#include <sva/dataset.hpp>
#include <sva/engine.hpp>
#include <sva/error.hpp>
#include <sva/eval/evaluation.hpp>
#include <sva/eval/trial_sessions.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>

#include <algorithm>
#include <cstdio>

#include "args.hpp"

namespace sva::cli {

namespace {

int write_sessions(const Args& a, const std::string& out_file) {
  const std::string data_file = a.required("--data"), map_file = a.required("--map");
  const Map map = Map::load(map_file);
  const Dataset test = load_dataset(data_file);
  eval::check_compatible(map, test, map_file, data_file);
  const auto n = static_cast<std::size_t>(a.integer("--trials", static_cast<long long>(map.objects()), 1, 10000000));
  const auto m = static_cast<std::size_t>(a.integer("--max-readings", 30, 1, 100000));
  const auto seed = static_cast<std::uint64_t>(a.integer("--seed", 1, 0, INT64_MAX));
  write_batch_sessions(out_file, eval::trial_sessions(test, map.pose_space(), seed, n, m, data_file));
  std::printf("wrote %zu sessions of %zu readings to %s\n", n, m, out_file.c_str());
  return 0;
}

}  // namespace

int cmd_recognize(const std::vector<std::string>& argv) {
  Args a("sva recognize",
         "Recognise a batch of independent sessions of readings (JSON Lines, docs/batch-format.md) and write one\n"
         "estimate per session (JSON Lines). All sessions step together: one backend update carries the next\n"
         "reading of every session, which keeps a GPU busy. With --write-sessions it instead writes a sessions file\n"
         "of evaluation trials (random poses of a test set's objects, ground truth included).",
         argv);
  a.option("--map", "MAP", "map file (sva train)")
      .option("--batch", "SESSIONS.jsonl", "the sessions to recognise")
      .option("--out", "RESULTS.jsonl", "where the estimates go")
      .option("--backend", "auto|cpu|vulkan", "vote backend (default auto: Vulkan when a device exists, else CPU)")
      .option("--sessions-per-submission", "N",
              "sessions stepped together (default: on a GPU as many as half its memory holds at "
              "--belief-budget, shared by the groups in flight, 64 to 4096 each; 64 on the CPU)")
      .option("--in-flight", "N",
              "groups of sessions recognised at once, on one recognizer each, so that the host prepares one "
              "group's update while the device runs another's (default: 2 on a GPU, 1 on the CPU)")
      .option("--device", "NAME|INDEX", "Vulkan device (default: prefer a discrete GPU; env SVA_VK_DEVICE)")
      .option("--top", "K", "hypotheses reported per session (default 3)")
      .option("--refine", "on|off", "fine pose: align the readings to the object's surface (default on)")
      .option("--surface-check", "on|off",
              "weigh the leading objects by how well their surfaces explain the readings (default on)")
      .option("--estimate", "full|light",
              "each session's estimate at its end: full (default) or light, the belief's answer without the host's "
              "fits (the parabolic pose, no surface check; docs/recognition.md, \"Light and full estimates\")")
      .option("--belief-budget", "BINS",
              "touched pose bins per session before hopeless ones are forgotten (default 4194304; 0 = no bound; "
              "32768 keeps a paper3d session of 30 readings near 4 MB in a batch; docs/batch-format.md)")
      .option("--max-pairs", "N",
              "bounded cost per update: pairs per update, both orders counted (default 0: the exact filter; "
              "docs/recognition.md)")
      .option("--likelihood-cutoff", "L",
              "matches whose likelihood (Eq 15, summed over the keys they share) is below L cast no vote (default 0: "
              "every match votes, the paper's method; the map's calibration was fitted at 0; docs/recognition.md, "
              "\"Fewer votes\")")
      .option("--write-sessions", "FILE.jsonl", "write trials as a sessions file instead (needs --map, --data)")
      .option("--data", "TEST", "test dataset for --write-sessions")
      .option("--trials", "N", "sessions to write (default: one per object)")
      .option("--max-readings", "M", "readings per written session (default 30)")
      .option("--seed", "S", "seed of the written trials (default 1)");
  if (!a.parse()) return 0;
  if (auto ws = a.get("--write-sessions")) return write_sessions(a, *ws);
  const std::string map_file = a.required("--map"), batch_file = a.required("--batch"), out_file = a.required("--out");
  const EstimateDepth depth = parse_estimate_depth(a.get_or("--estimate", "full"), "sva recognize: --estimate");
  const Map map = Map::load(map_file);
  // Checked whole first (a bad line anywhere stops it before any recognition), then streamed a group at a time.
  const BatchSessionsFile sessions(batch_file, map.sensor().elements());
  const auto top_k = static_cast<std::size_t>(a.integer("--top", 3, 0, 1000));
  RecognizerOptions ro;
  ro.backend = parse_backend_kind(a.get_or("--backend", "auto"), "sva recognize: --backend");
  ro.vulkan_device = a.get_or("--device", "");
  ro.refine_pose = a.on_off("--refine", ro.refine_pose);
  ro.surface_check = a.on_off("--surface-check", ro.surface_check);
  ro.belief_budget_bins = static_cast<std::size_t>(
      a.integer("--belief-budget", static_cast<long long>(ro.belief_budget_bins), 0, 1ll << 40));
  ro.max_pairs_per_update = static_cast<int>(a.integer("--max-pairs", 0, 0, 1 << 20));
  ro.likelihood_cutoff = static_cast<float>(a.number("--likelihood-cutoff", 0.0, 0.0, 128.0));

  const Engine engine(map, {ro.backend, ro.vulkan_device});
  const auto per = static_cast<std::size_t>(
      a.integer("--sessions-per-submission", static_cast<long long>(engine.sessions_per_submission(ro)), 1, 1 << 20));
  const auto in_flight =
      static_cast<std::size_t>(a.integer("--in-flight", static_cast<long long>(engine.submissions_in_flight()), 1, 8));
  std::vector<BatchRecognizer> recs = batch_recognizers(engine, sessions.sessions(), per, in_flight, ro);
  const BatchRecognizer& rec = recs.front();
  if (!rec.backend_fallback_reason().empty())
    std::fprintf(stderr, "sva recognize: backend auto chose the CPU reference: %s\n",
                 rec.backend_fallback_reason().c_str());
  sessions.recognize(recs, map, out_file, top_k, true, depth);
  std::fprintf(stderr,
               "recognised %zu sessions (%zu readings) with %s, %zu per submission, %zu in flight, %s estimates; "
               "wrote %s\n",
               sessions.sessions(), sessions.readings(), rec.backend_description().c_str(), rec.sessions(), recs.size(),
               estimate_depth_name(depth), out_file.c_str());
  return 0;
}

}  // namespace sva::cli
