// sva view: one session in the browser (docs/view.md). The session is an evaluation trial (--data, --trial: the
// trial `sva eval` runs with the same --seed and --max-readings) or a session of a sessions file (--sessions,
// --session or --id: a robot's readings, a replayed recording, a batch's session); the page is written by the
// tools' library (sva/eval/session_view.hpp); this file parses the options.
#include <sva/batch_file.hpp>
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/eval/evaluation.hpp>
#include <sva/eval/session_view.hpp>
#include <sva/eval/trials.hpp>
#include <sva/map.hpp>

#include <algorithm>
#include <cstdio>
#include <optional>

#include <nlohmann/json.hpp>
#include <sva/io/json.hpp>
#include "args.hpp"

namespace sva::cli {

namespace {

// The map's id of a scene object name, or none.
std::optional<std::uint32_t> map_object(const Map& map, const std::string& name) {
  const auto names = map.object_names();
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) return std::nullopt;
  return static_cast<std::uint32_t>(it - names.begin());
}

// A sessions file's truth ({"object": name, "R": rows, "T": mm}, as `sva recognize --write-sessions` writes it), from
// its JSON text (the reader has parsed it once: it is JSON).
std::optional<view::SessionTruth> truth_of(const Map& map, const std::string& text) {
  if (text.empty()) return std::nullopt;
  const nlohmann::json t = io::parse_json(text);
  if (!t.is_object() || !t.contains("object") || !t.contains("R") || !t.contains("T")) return std::nullopt;
  const auto object = map_object(map, t["object"].get<std::string>());
  if (!object) return std::nullopt;
  view::SessionTruth truth{*object, {}};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) truth.pose.R[c][r] = t["R"][r][c].get<double>();
  for (int k = 0; k < 3; ++k) truth.pose.T[k] = t["T"][k].get<double>();
  return truth;
}

struct Picked {
  std::vector<Reading> readings;
  std::optional<view::SessionTruth> truth;
  std::string title, source;
  std::optional<Scene> scene;
};

Picked from_trial(const Args& a, const Map& map, const std::string& map_file) {
  const std::string data_file = a.required("--data");
  const Dataset test = load_dataset(data_file);
  eval::check_compatible(map, test, map_file, data_file);
  const auto seed = static_cast<std::uint64_t>(a.integer("--seed", 1, 0, INT64_MAX));
  const auto max_readings = static_cast<std::size_t>(a.integer("--max-readings", 30, 1, 100000));
  const auto k = static_cast<std::size_t>(a.integer("--trial", 0, 0, 100000000));
  const eval::TrialGenerator generator(test, map.pose_space(), seed, max_readings, data_file);
  view::TrialView trial = view::trial_view(map, test, generator, k, seed, data_file);
  return {std::move(trial.readings), trial.truth, trial.title, trial.source, test.scene};
}

Picked from_sessions(const Args& a, const Map& map) {
  const std::string file = a.required("--sessions");
  auto sessions = read_batch_sessions(file, map.sensor().elements());
  std::size_t k = static_cast<std::size_t>(a.integer("--session", 0, 0, 100000000));
  if (auto id = a.get("--id")) {
    const auto it = std::find_if(sessions.begin(), sessions.end(), [&](const auto& s) { return s.id == *id; });
    if (it == sessions.end()) throw Error(file + ": no session with id \"" + *id + "\"");
    k = static_cast<std::size_t>(it - sessions.begin());
  } else if (k >= sessions.size()) {
    throw Error(file + ": session " + std::to_string(k) + " out of range (" + std::to_string(sessions.size()) +
                " sessions)");
  }
  Picked p;
  p.readings = std::move(sessions[k].readings);
  p.truth = truth_of(map, sessions[k].truth);
  p.title = "session " + sessions[k].id;
  p.source = file + ", session " + sessions[k].id;
  p.scene = load_scene(a.get_or("--scene", map.scene_name()));
  return p;
}

}  // namespace

int cmd_view(const std::vector<std::string>& argv) {
  Args a("sva view",
         "Write one session as a self-contained HTML page (three.js inlined; works offline): the object's true pose\n"
         "as a ghost, the hypotheses at their poses coloured by mass, the touches with their normals and numbers\n"
         "(their pressure images on hover), and a slider over the readings that updates the hypotheses, the object\n"
         "probabilities and the errors. The session is an evaluation trial (--data, --trial: as sva eval runs it with\n"
         "the same --seed and --max-readings) or a session of a sessions file (--sessions). docs/view.md.",
         argv);
  a.option("--map", "MAP", "map file (sva train)")
      .option("--out", "PAGE.html", "the page to write")
      .option("--data", "TEST", "test dataset: the session is evaluation trial --trial")
      .option("--trial", "K", "which trial, from 0 (default 0)")
      .option("--max-readings", "M", "readings of the trial (default 30, as sva eval)")
      .option("--seed", "S", "seed of the trials (default 1, as sva eval)")
      .option("--sessions", "FILE.jsonl", "sessions file (docs/batch-format.md): the session is --session or --id")
      .option("--session", "K", "which session, from 0 in file order (default 0)")
      .option("--id", "ID", "the session with this id")
      .option("--scene", "NAME|FILE",
              "with --sessions: the scene of the map's objects, for the meshes (default the map's)")
      .option("--top", "K", "hypotheses shown per reading (default 5)")
      .option("--backend", "auto|cpu|vulkan", "vote backend (default auto, as sva eval)")
      .option("--refine", "on|off", "fine pose (default on, as sva eval)")
      .option("--max-pairs", "N",
              "bounded cost per update for long sessions (default 0: the exact filter; "
              "docs/recognition.md)");
  if (!a.parse()) return 0;
  const std::string map_file = a.required("--map"), out = a.required("--out");
  if (a.has("--data") == a.has("--sessions"))
    throw Error("sva view: give exactly one of --data (a trial) or --sessions");
  const Map map = Map::load(map_file);
  Picked p = a.has("--data") ? from_trial(a, map, map_file) : from_sessions(a, map);
  view::SessionViewSpec spec;
  spec.title = p.title;
  spec.source = p.source;
  spec.map_name = map_file;
  spec.top_k = static_cast<std::size_t>(a.integer("--top", 5, 1, 100));
  spec.progress = true;
  spec.options.backend = parse_backend_kind(a.get_or("--backend", "auto"), "sva view: --backend");
  spec.options.refine_pose = a.on_off("--refine", true);
  spec.options.max_pairs_per_update = static_cast<int>(a.integer("--max-pairs", 0, 0, 1 << 20));
  const auto data = view::session_view_data(map, p.scene ? &*p.scene : nullptr, p.readings, p.truth, spec);
  for (const auto& w : data["warnings"]) std::fprintf(stderr, "sva view: %s\n", w.get<std::string>().c_str());
  view::write_session_page(out, data);
  std::fprintf(stderr, "wrote %s: %zu readings, %zu meshes\n", out.c_str(), p.readings.size(), data["meshes"].size());
  return 0;
}

}  // namespace sva::cli
