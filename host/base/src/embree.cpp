#include <sva/base/embree.hpp>

#include <embree3/rtcore.h>
#include <sva/base/parallel.hpp>
#include <sva/error.hpp>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <mutex>

namespace sva::embree {

namespace {

thread_local std::string t_error;

extern "C" void on_error(void*, RTCError code, const char* message) {
  t_error = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "(no message)");
}

std::string device_config() {
  // No "threads=N" unless asked: with TBB tasking, Embree turns a thread count into a process-wide TBB limit
  // (global_control), which capped every parallel loop of the process at that many threads. Builds may use the
  // pool; no answer depends on Embree's tree (the simulator's filter collects every candidate; the triangle tree
  // weighs every triangle within its margin).
  std::string config = "set_affinity=0";
  // SVA_THREADS (util::default_threads) caps Embree's pool too: a run asked for one thread starts no workers (under
  // qemu-user, oneTBB's worker start spins: scripts/aarch64-check.sh runs with SVA_THREADS=1).
  if (std::getenv("SVA_THREADS")) config += ",threads=" + std::to_string(util::default_threads());
  const char* isa = std::getenv("SVA_EMBREE_ISA");
  if (!isa || !*isa) return config;
  static const std::array<std::string, 5> known{"sse2", "sse4.2", "avx", "avx2", "avx512"};
  if (std::find(known.begin(), known.end(), isa) == known.end())
    throw Error(std::string("SVA_EMBREE_ISA=") + isa + ": not an Embree ISA (sse2, sse4.2, avx, avx2 or avx512)");
  return config + ",isa=" + isa;
}

}  // namespace

RTCDeviceTy* device() {
  static std::mutex mutex;
  static RTCDevice dev = nullptr;
  std::lock_guard lock(mutex);
  if (dev) return dev;
  const std::string config = device_config();
  dev = rtcNewDevice(config.c_str());
  if (!dev) {
    const RTCError e = rtcGetDeviceError(nullptr);
    throw Error("cannot create an Embree device with \"" + config + "\" (error " + std::to_string(static_cast<int>(e)) +
                ")" +
                (e == RTC_ERROR_UNSUPPORTED_CPU ? ": this CPU lacks the instruction set SVA_EMBREE_ISA names" : ""));
  }
  rtcSetDeviceErrorFunction(dev, on_error, nullptr);
  return dev;
}

void clear_error() { t_error.clear(); }

void SceneRelease::operator()(RTCSceneTy* scene) const { rtcReleaseScene(scene); }

void check(const std::string& what) {
  if (t_error.empty()) return;
  std::string e = std::move(t_error);
  t_error.clear();
  throw Error(what + ": " + e);
}

}  // namespace sva::embree
