// sva simulate: tactile readings of a scene's objects from the Embree
// simulator, written as DIR/train.svad and DIR/test.svad.
#include <sva/dataset.hpp>
#include <sva/scene.hpp>

#include <sva/base/parallel.hpp>
#include <sva/eval/dataset_export.hpp>

#include <cstdio>
#include <set>

#include "args.hpp"

#if __has_include(<sva/sim/simulate.hpp>)
#include <sva/sim/simulate.hpp>
#define SVA_HAVE_SIM 1
#endif

namespace sva::cli {

#ifdef SVA_HAVE_SIM
namespace {

// An ad-hoc scene of the given meshes with the paper3d defaults.
Scene scene_of_meshes(const std::vector<std::string>& meshes) {
  Scene s;
  s.name = "meshes";
  std::set<std::string> names;
  for (const auto& m : meshes) {
    SceneObject o;
    o.mesh = std::filesystem::absolute(m).lexically_normal();
    std::string base = o.mesh.stem().string();
    o.name = base.empty() ? "object" : base;
    for (int k = 2; !names.insert(o.name).second; ++k) o.name = base + "_" + std::to_string(k);
    s.objects.push_back(o);
  }
  // Read back as a scene file is, so that its names are checked as a file's (a control character in a mesh file's
  // name is refused here, not when sva train reads the dataset: docs/scene-format.md, "Names").
  parse_scene(scene_to_json(s), "sva simulate --mesh");
  return s;
}

void print_summary(const sim::SimulatedData& data, const std::filesystem::path& out) {
  for (const Dataset* d : {&data.train, &data.test}) {
    std::size_t conv = d->count_converged(), n = d->samples.size(), no_contact = 0;
    double iters = 0;
    for (const auto& s : d->samples) {
      no_contact += s.reading.status == ControllerStatus::no_contact;
      iters += s.reading.iterations;
    }
    std::printf("%-5s %6zu readings: %6zu converged, %5zu not converged, %5zu no contact; %.1f iterations on average\n",
                d->split.c_str(), n, conv, n - conv - no_contact, no_contact, n ? iters / static_cast<double>(n) : 0.0);
  }
  std::printf("wrote %s and %s\n", (out / "train.svad").c_str(), (out / "test.svad").c_str());
}

}  // namespace

int cmd_simulate(const std::vector<std::string>& argv) {
  Args a("sva simulate",
         "Simulate tactile readings of a scene's objects (Embree ray casting, compliant skin, contact controller)\n"
         "and write DIR/train.svad and DIR/test.svad. Same seed, same bytes, whatever --threads.",
         argv);
  std::string builtin;  // from the list itself, so that the help never leaves a scene out
  for (const std::string& name : builtin_scene_names()) builtin += (builtin.empty() ? "" : ", ") + name;
  a.option("--scene", "NAME|FILE", "a built-in scene (" + builtin + ") or a scene JSON file")
      .option("--mesh", "FILE", "a glTF mesh (.gltf/.glb): an ad-hoc scene with the paper3d defaults", true)
      .option("--out", "DIR", "output directory (created if needed)")
      .option("--train", "N", "training readings per object (default: the scene's protocol)")
      .option("--test", "N", "test readings per object (default: the scene's protocol)")
      .option("--seed", "S", "random seed (default 1)")
      .option("--error-scale", "X",
              "multiply every sigma and spread of the scene's errors block (default 1; 0: the ideal world)")
      .option("--preview", "FILE.png", "also write a contact sheet of training readings")
      .option("--threads", "N", "worker threads (default: SVA_THREADS or all cores)");
  if (!a.parse()) return 0;
  const bool has_scene = a.has("--scene"), has_mesh = a.has("--mesh");
  if (has_scene == has_mesh) throw Error("sva simulate: give either --scene or --mesh (see sva simulate --help)");
  const std::filesystem::path out = a.required("--out");
  sim::SimulateOptions opt;
  opt.train_per_object = static_cast<int>(a.integer("--train", -1, 0, 10000000));
  opt.test_per_object = static_cast<int>(a.integer("--test", -1, 0, 10000000));
  opt.seed = static_cast<std::uint64_t>(a.integer("--seed", 1, 0, std::numeric_limits<long long>::max()));
  opt.threads = static_cast<unsigned>(a.integer("--threads", 0, 1, 1024));
  opt.error_scale = a.number("--error-scale", 1.0, 0.0, 1000.0);
  std::string preview = a.get_or("--preview", "");
  if (a.has("--preview") && preview.empty()) throw Error("sva simulate: --preview needs a file name");

  Scene scene = has_scene ? load_scene(a.required("--scene")) : scene_of_meshes(a.all("--mesh"));
  std::error_code ec;
  if (std::filesystem::exists(out, ec) && !std::filesystem::is_directory(out, ec))
    throw Error(out.string() + ": exists and is not a directory");
  sim::SimulatedData data = sim::simulate(scene, opt);  // all inputs validated before anything is written
  std::filesystem::create_directories(out, ec);
  if (ec) throw Error(out.string() + ": cannot create directory: " + ec.message());
  save_dataset(data.train, out / "train.svad");
  save_dataset(data.test, out / "test.svad");
  if (!preview.empty()) {
    io::write_preview(data.train, preview);
    std::printf("wrote %s\n", preview.c_str());
  }
  print_summary(data, out);
  return 0;
}
#else
int cmd_simulate(const std::vector<std::string>&) {
  throw Error("sva simulate: this build has no simulator (configure with -DSVA_BUILD_SIM=ON and Embree 3)");
}
#endif

}  // namespace sva::cli
