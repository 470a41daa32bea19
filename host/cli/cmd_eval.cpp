// sva eval: recognition trials on test readings (paper Sec 5); prints the
// curve and writes the JSON summary, the per-step CSV and the figure.
#include <sva/dataset.hpp>
#include <sva/eval/session_view.hpp>
#include <sva/map.hpp>
#include <sva/recognizer.hpp>

#include <sva/eval/confusion.hpp>
#include <sva/eval/evaluation.hpp>
#include <sva/eval/figure.hpp>
#include <sva/eval/mesh_symmetry.hpp>
#include <sva/eval/report.hpp>
#include <sva/eval/results.hpp>
#include <sva/eval/robustness.hpp>
#include <sva/io/text_file.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "args.hpp"

#if __has_include(<sva/sim/touch_simulator.hpp>)
#include <sva/sim/touch_simulator.hpp>
#define SVA_HAVE_SIM 1
#endif

namespace sva::cli {

namespace {

// Refuse an output path whose directory is missing before hours of trials.
void check_writable(const std::string& option, const std::string& file) {
  if (file.empty()) throw Error("sva eval: " + option + " needs a file name");
  const auto dir = std::filesystem::path(file).parent_path();
  std::error_code ec;
  if (!dir.empty() && !std::filesystem::is_directory(dir, ec))
    throw Error("sva eval: " + option + " " + file + ": directory " + dir.string() + " does not exist");
}

std::vector<std::size_t> parse_reading_counts(const std::string& text, const char* option = "--sweep-readings") {
  std::vector<std::size_t> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const long v = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || v < 1 || v > 100000)
      throw Error(std::string("sva eval: ") + option + " expects a list like 5,10,20,30, got \"" + text + "\"");
    out.push_back(static_cast<std::size_t>(v));
  }
  return out;
}

// The robustness sweep's report: no trials, only the summaries of runs at
// several error levels, tabulated and drawn against the level.
int sweep_report(const Args& a) {
  const auto plot_file = a.get("--plot"), table_file = a.get("--table");
  if (plot_file) check_writable("--plot", *plot_file);
  if (table_file) check_writable("--table", *table_file);
  for (const char* o : {"--map", "--data", "--json", "--csv", "--evidence", "--compare"})
    if (a.has(o)) throw Error(std::string("sva eval: --sweep reports earlier runs; ") + o + " does not apply");
  std::vector<eval::SweepLevel> levels;
  for (const auto& arg : a.all("--sweep")) levels.push_back(eval::read_sweep_level(arg));
  const auto readings = parse_reading_counts(a.get_or("--sweep-readings", "5,10,20,30"));
  eval::check_sweep(levels, readings);
  const std::string table = eval::format_sweep_table(levels, readings);
  std::fputs(table.c_str(), stdout);
  if (table_file) io::write_text_file(*table_file, table);
  if (plot_file) eval::write_sweep_figure(levels, readings, *plot_file);
  return 0;
}

// --confusion's reading counts: the ones asked for (each within the run), by default 15 and 30 where the run has
// them, else its last reading.
std::vector<std::size_t> confusion_counts(const Args& a, std::size_t max_readings) {
  if (a.has("--confusion-at")) {
    const auto counts = parse_reading_counts(*a.get("--confusion-at"), "--confusion-at");
    for (std::size_t n : counts)
      if (n > max_readings)
        throw Error("sva eval: --confusion-at " + std::to_string(n) + " is beyond --max-readings " +
                    std::to_string(max_readings));
    return counts;
  }
  std::vector<std::size_t> counts;
  for (std::size_t n : {15u, 30u})
    if (n <= max_readings) counts.push_back(n);
  if (counts.empty()) counts.push_back(max_readings);
  return counts;
}

// The confusion tables on stdout, the matrices as JSON and the last one as FILE.png beside it.
void write_confusions(const eval::EvalResult& result, const std::vector<std::size_t>& counts,
                      const std::string& json_file) {
  std::vector<eval::Confusion> confusions;
  for (std::size_t n : counts) confusions.push_back(eval::confusion_at(result, n));
  std::fputs(eval::format_confusion_tables(confusions).c_str(), stdout);
  io::write_text_file(json_file, eval::confusion_json(confusions));
  const std::filesystem::path p(json_file);
  eval::write_confusion_figure(confusions.back(), result.scene, p.parent_path() / (p.stem().string() + ".png"));
}

// --policy active-sim: the scene's meshes loaded once, every planned touch pressed on its trial's object.
eval::TouchSimulator touch_simulator(const Scene& scene, const std::string& data_file) {
#ifdef SVA_HAVE_SIM
  std::shared_ptr<const sim::TouchSimulator> press;
  try {
    press = std::make_shared<const sim::TouchSimulator>(scene);
  } catch (const Error& e) {
    throw Error("sva eval: --policy active-sim presses the planned touches on the scene's meshes, and " + data_file +
                "'s scene cannot be simulated here: " + e.what());
  }
  return [press](const eval::Trial& trial, const CandidateTouch& touch, std::uint64_t seed) {
    return press->press(trial.object, trial.pose, touch, seed);
  };
#else
  (void)scene;
  throw Error("sva eval: --policy active-sim needs the simulator, and this sva was built without it (" + data_file +
              ")");
#endif
}

// The options every eval run takes (everything but the files), checked.
eval::EvalOptions eval_options(const Args& a) {
  eval::EvalOptions o;
  o.max_readings = static_cast<std::size_t>(a.integer("--max-readings", 30, 1, 100000));
  o.seed = static_cast<std::uint64_t>(a.integer("--seed", 1, 0, std::numeric_limits<long long>::max()));
  o.threads = static_cast<unsigned>(a.integer("--threads", 0, 1, 1024));
  o.recognizer.backend = parse_backend_kind(a.get_or("--backend", "auto"), "sva eval: --backend");
  const std::string method = a.get_or("--method", "sva");
  if (method == "sva")
    o.recognizer.method = Method::sva;
  else if (method == "appearance")
    o.recognizer.method = Method::appearance;
  else
    throw Error("sva eval: --method expects sva or appearance, got \"" + method + "\"");
  o.recognizer.eps = a.number("--eps", o.recognizer.eps, 1e-300, 1.0);
  if (a.has("--eps") && !(o.recognizer.eps > 0)) throw Error("sva eval: --eps must be positive");
  o.recognizer.refine_pose = a.on_off("--refine", o.recognizer.refine_pose);
  o.recognizer.surface_check = a.on_off("--surface-check", o.recognizer.surface_check);
  o.estimate = parse_estimate_depth(a.get_or("--estimate", "full"), "sva eval: --estimate");
  o.recognizer.belief_budget_bins = static_cast<std::size_t>(
      a.integer("--belief-budget", static_cast<long long>(o.recognizer.belief_budget_bins), 0, 1ll << 40));
  o.recognizer.max_pairs_per_update = static_cast<int>(a.integer("--max-pairs", 0, 0, 1 << 20));
  o.recognizer.likelihood_cutoff = static_cast<float>(a.number("--likelihood-cutoff", 0.0, 0.0, 128.0));
  o.recognizer.calibrate = a.on_off("--calibration", o.recognizer.calibrate);
  o.recognizer.unknown_prior = a.number("--unknown-prior", o.recognizer.unknown_prior, 1e-9, 1.0 - 1e-9);
  o.unknown_objects = a.has("--unknown-objects");
  if (a.has("--stop-at")) o.stop_at = a.number("--stop-at", 0.95, 0.5, 1.0 - 1e-12);
  o.policy = eval::parse_policy(a.get_or("--policy", "random"), "sva eval: --policy");
  if (o.policy == eval::Policy::random)
    for (const char* opt : {"--candidates", "--candidates-from", "--plan-hypotheses", "--plan-second"})
      if (a.has(opt)) throw Error(std::string("sva eval: ") + opt + " needs --policy active or active-sim");
  o.active.candidates = static_cast<std::size_t>(a.integer("--candidates", 100, 1, 1000000));
  o.active.hypotheses = static_cast<std::size_t>(a.integer("--plan-hypotheses", 8, 1, 64));
  const std::string from = a.get_or("--candidates-from", "object");
  if (from != "hypotheses" && from != "object")
    throw Error("sva eval: --candidates-from expects hypotheses or object, got \"" + from + "\"");
  o.active.candidates_on_object = from == "object";
  if (o.active.candidates_on_object && a.has("--candidates"))
    throw Error(
        "sva eval: --candidates N samples candidates on the hypotheses' surfaces: it needs --candidates-from "
        "hypotheses");
  o.active.contact_hypotheses = static_cast<std::size_t>(a.integer("--plan-second", 6, 0, 64));
  return o;
}

// --compare's curves, checked against this run's scene, labelled for the figure.
std::vector<eval::Curve> compared_curves(const std::vector<std::string>& files, const Map& map,
                                         const eval::EvalOptions& o) {
  const std::string method = o.recognizer.method == Method::sva ? "sva" : "appearance";
  std::vector<eval::Curve> others;
  for (const auto& f : files) {
    eval::Curve c = eval::read_curve_json(f);
    if (c.scene != map.scene_name())
      throw Error("sva eval: --compare " + f + " is from scene \"" + c.scene + "\", this run is on \"" +
                  map.scene_name() + "\"");
    if (c.method == method && c.policy == eval::policy_name(o.policy))
      c.label = std::filesystem::path(f).stem().string();
    else if (c.method == "sva" && c.policy == "random" && o.policy != eval::Policy::random)
      c.label = "sva random";  // beside the active policies' curves
    others.push_back(std::move(c));
  }
  return others;
}

void declare_eval_options(Args& a) {
  a.option("--map", "MAP", "map file (sva train)");
  a.option("--data", "TEST", "test dataset (sva simulate ... test.svad)");
  a.option("--trials", "N", "trials (default: 3 repetitions x objects, as in the paper)");
  a.option("--max-readings", "M", "readings per trial (default 30)");
  a.option("--seed", "S", "seed of the poses and reading orders (default 1)");
  a.option("--backend", "auto|cpu|vulkan", "vote backend (default auto: Vulkan when a device is usable, else CPU)");
  a.option("--method", "sva|appearance", "sva, or the appearance-only baseline of [15] (default sva)");
  a.option("--json", "OUT.json", "write the summary curve as JSON");
  a.option("--csv", "OUT.csv", "write one row per (trial, readings)");
  a.option("--evidence", "OUT.jsonl",
           "write what each estimate's object posterior was made of, a line per (trial, readings): the pairs' and the "
           "surface check's bits per object, to weigh them otherwise offline (docs/evaluation.md)");
  a.option("--html", "DIR",
           "write a page per trial (sva view's: the touches and hypotheses in 3-D, reading by reading), "
           "the accuracy figure and an index with the worst trials first (random policy; docs/view.md)");
  a.option("--plot", "OUT.png", "write the figure (accuracy and errors against readings, like the paper's Fig. 4/5)");
  a.option("--reliability", "OUT.png",
           "write the reliability diagram: accuracy against the top object's probability (docs/evaluation.md; "
           "default with --plot FIG.png: FIG_reliability.png beside it)");
  a.option("--calibration", "on|off",
           "calibrated probabilities and \"none of these\" (default on; off: Eq 5's product as it stands)");
  a.option("--unknown-prior", "P", "prior probability that a touched object is none of the map's (default 0.1)");
  a.flag("--unknown-objects",
         "the test set may hold objects the map does not (a map trained with sva train --exclude-objects): their "
         "trials are right only when they say \"none of these\"; prints the ROC of p_unknown");
  a.option("--confusion", "OUT.json",
           "write the confusion matrices (and OUT.png, the last one ordered by look-alike family) and print the "
           "accuracy per object and per family (docs/evaluation.md, \"Look-alikes\")");
  a.option("--confusion-at", "LIST", "with --confusion: the reading counts (default 15,30 within --max-readings)");
  a.option("--stop-at", "P",
           "report deciding at probability P: the first reading where the top object or \"none of these\" "
           "reaches P, the readings used and the decisions' accuracy");
  a.option("--compare", "OTHER.json", "add another run's curve (e.g. the other method) to the figure", true);
  a.option("--threads", "N", "trials run in parallel (default: SVA_THREADS or all cores); results do not depend on it");
  a.option("--eps", "E", "floor of every pair factor (default 1e-6; docs/recognition.md)");
  a.option("--surface-check", "on|off",
           "weigh the three leading objects by how well their surfaces explain the readings, from 6 readings on "
           "(default on; docs/recognition.md, \"Surface check\")");
  a.option("--refine", "on|off",
           "fine pose: align the readings to the object's surface (default on; docs/recognition.md)");
  a.option("--estimate", "full|light",
           "each step's estimate: full (default) or light, the belief's answer without the host's fits (the "
           "parabolic pose, no surface check; docs/recognition.md, \"Light and full estimates\")");
  a.option("--max-pairs", "N",
           "bounded cost per update: pairs per update, both orders counted (58: the new reading with the 29 most "
           "recent ones; default 0, every earlier reading: the exact filter; docs/recognition.md)");
  a.option("--likelihood-cutoff", "L",
           "matches whose likelihood (Eq 15, summed over the keys they share) is below L cast no vote (default 0: "
           "every match votes, the paper's method; the map's calibration was fitted at 0; docs/recognition.md)");
  a.option("--belief-budget", "BINS",
           "touched pose bins per session before hopeless ones are forgotten (default 4194304; 0 = no bound)");
  a.option("--policy", "random|active|active-sim",
           "how each next reading is chosen: random test readings (default, the paper's protocol), the test "
           "reading nearest to the planned touch (active), or the planned touch pressed on the scene's mesh "
           "(active-sim); docs/evaluation.md, \"Choosing the next touch\"");
  a.option("--candidates", "N",
           "active policies with --candidates-from hypotheses: candidate touches sampled per plan (default 100)");
  a.option("--plan-hypotheses", "K", "active policies: hypotheses of the estimate the plan tells apart (default 8)");
  a.option("--candidates-from", "hypotheses|object",
           "active policies: the candidate touches: the true object's unused test contacts in its true pose "
           "(default: the surface a robot's camera offers, not which object it is), or --candidates sampled on the "
           "hypotheses' surfaces");
  a.option("--plan-second", "K",
           "active policies: plan the second touch over K guesses per object from the first touch's appearance "
           "(TouchPlanner::contact_estimate; default 6; 0: the second touch is random, as the first)");
  a.option("--sweep", "LEVEL=RUN.json",
           "report mode (no trials): a robustness sweep's runs, one per error level; prints a table of "
           "accuracy and pose errors against the level, --plot draws them (bench/accuracy/robustness_sweep.sh)",
           true);
  a.option("--sweep-readings", "LIST", "with --sweep: the reading counts to report (default 5,10,20,30)");
  a.option("--table", "OUT.md", "with --sweep: also write the table to this file");
}

}  // namespace

int cmd_eval(const std::vector<std::string>& argv) {
  Args a("sva eval",
         "Run recognition trials: each trial takes an object (cycling through the objects), a random pose from the "
         "map's pose space and that object's test readings, transformed by the pose, in random order; after every "
         "reading it records whether the object is right, the translational, angular (with the object's symmetries) "
         "and inertial errors, MSSD and ADD-S (with the symmetries found on the object's mesh; docs/pose-errors.md), "
         "and the update time. Warns where the scene's declared symmetry and the mesh's disagree. Prints the curve; "
         "see docs/evaluation.md.",
         argv);
  declare_eval_options(a);
  if (!a.parse()) return 0;
  if (a.has("--sweep")) return sweep_report(a);
  for (const char* o : {"--sweep-readings", "--table"})
    if (a.has(o)) throw Error(std::string("sva eval: ") + o + " needs --sweep");

  const std::string map_file = a.required("--map");
  const std::string data_file = a.required("--data");
  eval::EvalOptions o = eval_options(a);
  const auto json_file = a.get("--json"), csv_file = a.get("--csv"), plot_file = a.get("--plot");
  auto reliability_file = a.get("--reliability");
  if (reliability_file) check_writable("--reliability", *reliability_file);
  const bool reliability_beside_plot = !reliability_file && plot_file;
  if (json_file) check_writable("--json", *json_file);
  if (csv_file) check_writable("--csv", *csv_file);
  const auto evidence_file = a.get("--evidence");
  if (evidence_file) check_writable("--evidence", *evidence_file);
  o.keep_evidence = evidence_file.has_value();
  if (plot_file) check_writable("--plot", *plot_file);
  const auto confusion_file = a.get("--confusion");
  if (confusion_file) check_writable("--confusion", *confusion_file);
  if (a.has("--confusion-at") && !confusion_file) throw Error("sva eval: --confusion-at needs --confusion");
  if (a.has("--html") && o.policy != eval::Policy::random)
    throw Error("sva eval: --html makes pages of the random policy's trials; drop --policy or --html");
  const std::vector<std::size_t> confusion_at = confusion_counts(a, o.max_readings);
  const auto compare_files = a.all("--compare");
  if (!compare_files.empty() && !plot_file)
    throw Error("sva eval: --compare adds curves to the figure; give --plot too");
  long long trials_arg = -1;
  if (a.has("--trials")) trials_arg = a.integer("--trials", 0, 1, 100000000);

  o.data_name = data_file;
  o.map_name = map_file;
  const Dataset test = load_dataset(data_file);
  const Map map = Map::load(map_file);
  eval::check_compatible(map, test, map_file, data_file, o.unknown_objects);
  // The scene's declared symmetries (the angle error's) against its meshes' (MSSD's): docs/pose-errors.md.
  for (const std::string& w : eval::symmetry_warnings(test.scene))
    std::fprintf(stderr, "sva eval: warning: %s\n", w.c_str());
  if (const std::string w = eval::light_calibration_warning(map, map_file, o.estimate, o.recognizer.calibrate);
      !w.empty())
    std::fprintf(stderr, "sva eval: warning: %s\n", w.c_str());
  o.trials = trials_arg > 0 ? static_cast<std::size_t>(trials_arg) : 3 * test.scene.objects.size();
  if (o.policy == eval::Policy::active_sim) o.active.simulate = touch_simulator(test.scene, data_file);
  const std::vector<eval::Curve> others = compared_curves(compare_files, map, o);

  const eval::EvalResult result = eval::run_evaluation(map, test, o);
  if (!result.backend_fallback_reason.empty())
    std::fprintf(stderr, "sva eval: backend auto chose the CPU reference: %s\n",
                 result.backend_fallback_reason.c_str());
  const eval::Curve curve = eval::summarize(result, o.stop_at);
  std::fputs(eval::format_table(curve).c_str(), stdout);
  if (json_file) io::write_text_file(*json_file, eval::to_json(result, curve));
  if (csv_file) io::write_text_file(*csv_file, eval::to_csv(result));
  if (evidence_file) io::write_text_file(*evidence_file, eval::to_evidence_jsonl(result));
  if (plot_file) {
    std::vector<eval::Curve> curves{curve};
    curves.insert(curves.end(), others.begin(), others.end());
    eval::write_figure(curves, *plot_file);
  }
  // The reliability diagram goes beside the accuracy figure (FIG_reliability.png) when it has trial-readings to show.
  if (reliability_beside_plot && curve.calibration.trial_readings > 0) {
    const std::filesystem::path p(*plot_file);
    reliability_file = (p.parent_path() / (p.stem().string() + "_reliability" + p.extension().string())).string();
  }
  if (reliability_file) eval::write_reliability_figure(curve, *reliability_file);
  if (confusion_file) write_confusions(result, confusion_at, *confusion_file);
  if (const auto html = a.get("--html")) {
    const std::size_t pages = view::write_trial_pages(*html, map, test, o, result, curve);
    std::fprintf(stderr, "sva eval: wrote %zu trial pages and %s/index.html\n", pages, html->c_str());
  }
  return 0;
}

}  // namespace sva::cli
