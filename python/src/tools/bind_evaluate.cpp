// sva.evaluate: the recognition trials of `sva eval` (docs/evaluation.md), with the GIL released and Ctrl-C reaching
// the engine; the JSON summary returned as a dict, the files written as the command writes them.
#include <sva/error.hpp>
#include <sva/eval/evaluation.hpp>
#include <sva/eval/figure.hpp>
#include <sva/eval/report.hpp>
#include <sva/io/text_file.hpp>

#include <nanobind/stl/filesystem.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/string.h>

#include <filesystem>
#include <optional>

#include "../arguments.hpp"
#include "../recognizer_options.hpp"
#include "tools.hpp"

namespace sva::python {

using namespace nb::literals;

namespace {

struct EvalFiles {
  std::optional<std::filesystem::path> json, csv, plot;
};

std::string evaluate(const MapArg& map, const DatasetArg& test, eval::EvalOptions o, const EvalFiles& files) {
  EngineScope scope(true);
  eval::check_compatible(map.map, *test.data, map.name, test.name);
  if (o.trials == 0) o.trials = 3 * test.data->scene.objects.size();
  const eval::EvalResult result = eval::run_evaluation(map.map, *test.data, o);
  const eval::Curve curve = eval::summarize(result);
  const std::string json = eval::to_json(result, curve);
  if (files.json) io::write_text_file(*files.json, json);
  if (files.csv) io::write_text_file(*files.csv, eval::to_csv(result));
  if (files.plot) eval::write_figure({curve}, *files.plot);
  return json;
}

nb::object evaluate_py(nb::handle map_obj, nb::handle data_obj, std::optional<std::size_t> trials,
                       std::size_t max_readings, std::uint64_t seed, unsigned threads, const EvalFiles& files,
                       const nb::kwargs& options) {
  eval::EvalOptions o;
  o.recognizer = recognizer_options(options, "sva.evaluate");
  if (trials && *trials == 0) throw Error("sva.evaluate: trials must be >= 1");
  o.trials = trials.value_or(0);
  if (max_readings == 0) throw Error("sva.evaluate: max_readings must be >= 1");
  o.max_readings = max_readings;
  o.seed = seed;
  o.threads = threads;
  o.progress = true;  // shown when sva.show_progress(True)
  const MapArg map = map_arg(map_obj, "sva.evaluate: map");
  const DatasetArg test = dataset_arg(data_obj, "sva.evaluate: data");
  o.map_name = map.name;
  o.data_name = test.name;
  const std::string json = evaluate(map, test, o, files);
  return nb::module_::import_("json").attr("loads")(json);
}

}  // namespace

void bind_evaluate(nb::module_& m) {
  m.def(
      "evaluate",
      [](nb::handle map, nb::handle data, std::optional<std::size_t> trials, std::size_t max_readings,
         std::uint64_t seed, unsigned threads, std::optional<std::filesystem::path> json,
         std::optional<std::filesystem::path> csv, std::optional<std::filesystem::path> plot,
         const nb::kwargs& options) {
        return evaluate_py(map, data, trials, max_readings, seed, threads, EvalFiles{json, csv, plot}, options);
      },
      "map"_a, "data"_a, nb::kw_only(), "trials"_a = nb::none(), "max_readings"_a = 30, "seed"_a = 1, "threads"_a = 0,
      "json"_a = nb::none(), "csv"_a = nb::none(), "plot"_a = nb::none(), "options"_a,
      nb::sig("def evaluate(map: sva.Map | str | os.PathLike, data: sva.Dataset | str | os.PathLike, *, trials: int | "
              "None = "
              "None, max_readings: int = 30, seed: int = 1, threads: int = 0, json: str | os.PathLike | None = None, "
              "csv: str | os.PathLike | None = None, plot: str | os.PathLike | None = "
              "None, " RECOGNIZER_OPTIONS_SIG_NO_THREADS ") -> dict[str, typing.Any]"),
      "Recognition trials of a map on a test set, as `sva eval` runs them (docs/evaluation.md): returns the JSON "
      "summary as a dict (the curve against the number of readings); `json`, `csv` and `plot` also write the "
      "files. Trials default to 3 per object.");
}

}  // namespace sva::python
