// The entry points of the commands, as functions: sva.simulate (sva simulate) and sva.train (sva train); sva.evaluate
// (sva eval) is the tools' module's (tools/bind_evaluate.cpp). They call the library functions the CLI calls, with
// the GIL released and Ctrl-C reaching the engine.
#include <sva/dataset.hpp>
#include <sva/error.hpp>
#include <sva/map.hpp>
#include <sva/scene.hpp>

#include <sva/base/progress.hpp>

#include <nanobind/stl/filesystem.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include "arguments.hpp"
#include "bindings.hpp"

#if __has_include(<sva/sim/simulate.hpp>)
#include <sva/sim/mesh.hpp>
#include <sva/sim/simulate.hpp>
#define SVA_HAVE_SIM 1
#endif

namespace sva::python {

using namespace nb::literals;

namespace {

std::pair<Dataset, Dataset> simulate(nb::handle scene_arg, std::optional<int> train, std::optional<int> test,
                                     std::uint64_t seed, unsigned threads,
                                     const std::optional<std::filesystem::path>& out,
                                     const std::optional<std::filesystem::path>& preview) {
#ifdef SVA_HAVE_SIM
  Scene scene;
  if (!nb::try_cast(scene_arg, scene, false)) {
    std::string name;
    if (!nb::try_cast(scene_arg, name))
      throw nb::type_error("sva.simulate: scene expects a Scene, a built-in scene's name or a scene file");
    scene = load_scene(name);
  }
  sim::SimulateOptions opt;
  opt.train_per_object = train.value_or(-1);
  opt.test_per_object = test.value_or(-1);
  if (opt.train_per_object < -1 || opt.test_per_object < -1)
    throw Error("sva.simulate: train and test are readings per object, >= 0");
  opt.seed = seed;
  opt.threads = threads;
  sim::SimulatedData data;
  {
    EngineScope scope(true);
    std::error_code ec;
    if (out && std::filesystem::exists(*out, ec) && !std::filesystem::is_directory(*out, ec))
      throw Error(out->string() + ": exists and is not a directory");
    data = sim::simulate(scene, opt);  // all inputs validated before anything is written
    if (out) {
      std::filesystem::create_directories(*out, ec);
      if (ec) throw Error(out->string() + ": cannot create directory: " + ec.message());
      save_dataset(data.train, *out / "train.svad");
      save_dataset(data.test, *out / "test.svad");
    }
  }
  // The preview is a figure: the tools' module draws it (loaded now, so that `import sva` needs no cairo).
  if (preview) tools_module().attr("_write_preview")(nb::cast(&data.train, nb::rv_policy::reference), *preview);
  // The images have the scene's sensor's shape, as in a loaded dataset (Reading.pressure is then 2-D).
  for (Dataset* d : {&data.train, &data.test})
    for (Sample& s : d->samples) {
      s.reading.rows = d->scene.sensor.rows;
      s.reading.cols = d->scene.sensor.cols;
    }
  return {std::move(data.train), std::move(data.test)};
#else
  (void)scene_arg, (void)train, (void)test, (void)seed, (void)threads, (void)out, (void)preview;
  throw Error("sva.simulate: this build has no simulator (configure with -DSVA_BUILD_SIM=ON and Embree 3)");
#endif
}

Map train(nb::handle data_arg, const std::optional<std::string>& descriptor, std::optional<int> clusters,
          std::optional<int> dist_bins, std::optional<std::pair<double, double>> dist_range, std::uint64_t seed,
          unsigned threads, const std::optional<std::filesystem::path>& out, TrainReport* report, bool calibrate,
          std::optional<std::size_t> pair_readings, std::optional<std::uint32_t> fine_pose_from, bool surfaces) {
  TrainOptions o;
  o.pair_readings = pair_readings;
  o.fine_pose_from = fine_pose_from;
  o.calibrate = calibrate;
  o.descriptor = descriptor;
  o.clusters = clusters;
  o.dist_bins = dist_bins;
  if (dist_range) std::tie(o.dist_min_mm, o.dist_max_mm) = *dist_range;
  o.seed = seed;
  o.threads = threads;
  o.progress = true;        // shown when sva.show_progress(True)
  o.validate("sva.train");  // before the dataset loads
  const DatasetArg data = dataset_arg(data_arg, "sva.train: data");
#ifdef SVA_HAVE_SIM
  if (surfaces) {
    try {
      o.surfaces = sim::object_surfaces(data.data->scene);
    } catch (const Error& e) {
      throw Error(std::string("sva.train: ") + e.what() +
                  " (surfaces=False trains without the objects' meshes: the verify stage then reads the training "
                  "contacts)");
    }
  }
#else
  (void)surfaces;
#endif
  EngineScope scope(true);
  Map map = Map::train(*data.data, o, report);
  if (out) map.save(*out);
  return map;
}

}  // namespace

void bind_workflow(nb::module_& m) {
  // Progress lines on stderr suit the command line; a Python program asks for them.
  util::Progress::set_quiet(true);
  static bool shown = false;
  m.def(
      "show_progress",
      [](bool on) {
        util::Progress::set_quiet(!on);
        // The tools' module has its own copy of the setting (its own copy of the library): told too when loaded,
        // and it reads _progress_shown when it loads.
        shown = on;
        if (nb::object tools = loaded_tools_module(); tools.is_valid()) tools.attr("_show_progress")(on);
      },
      "on"_a = true, "Show the progress of simulation, training and evaluation on stderr (off by default).");
  m.def("_progress_shown", [] { return shown; });
  m.def("simulate", &simulate, "scene"_a, nb::kw_only(), "train"_a = nb::none(), "test"_a = nb::none(), "seed"_a = 1,
        "threads"_a = 0, "out"_a = nb::none(), "preview"_a = nb::none(),
        nb::sig("def simulate(scene: Scene | str, *, train: int | None = None, test: int | None = None, seed: int = 1, "
                "threads: int = 0, out: str | os.PathLike | None = None, preview: str | os.PathLike | None = None) "
                "-> tuple[Dataset, Dataset]"),
        "Simulated (train, test) datasets of a scene (a Scene, a built-in scene's name or a scene file), `train` and "
        "`test` readings per object (default: the scene's protocol); with `out`, also written as out/train.svad and "
        "out/test.svad, as `sva simulate` does. Same seed, same data, whatever `threads`.");
  m.def("train", &train, "data"_a, nb::kw_only(), "descriptor"_a = nb::none(), "clusters"_a = nb::none(),
        "dist_bins"_a = nb::none(), "dist_range"_a = nb::none(), "seed"_a = 1, "threads"_a = 0, "out"_a = nb::none(),
        "report"_a = nb::none(), "calibrate"_a = true, "pair_readings"_a = nb::none(), "fine_pose_from"_a = nb::none(),
        "surfaces"_a = true,
        nb::sig("def train(data: Dataset | str | os.PathLike, *, descriptor: str | None = None, clusters: int | None = "
                "None, dist_bins: int | None = None, dist_range: tuple[float, float] | None = None, seed: int = 1, "
                "threads: int = 0, out: str | os.PathLike | None = None, report: TrainReport | None = None, "
                "calibrate: bool = True, pair_readings: int | None = None, fine_pose_from: int | None = None, "
                "surfaces: bool = True) -> Map"),
        "The SVA map of a training dataset, as `sva train` builds it (defaults from the dataset's scene); with `out`, "
        "also saved there; `report` (a TrainReport) is filled in. `pair_readings`: readings per object that enter the "
        "pairs (drawn at random; the rest serve only as the object's surface; 0 = all; default: the scene's). "
        "`fine_pose_from`: readings from which the fine pose and the surface check run, kept in the map (3 to 1000; "
        "default 6, planar 3; 4 names distinct objects right sooner and trusts twins less: docs/evaluation.md). "
        "`surfaces`: the objects' meshes in the map, for the verify stage's measurement model (False: a dataset of "
        "a real sensor's recordings; the training contacts instead).");
}

}  // namespace sva::python
