#pragma once
// The process's one Embree device, the one home of it: the simulator's rays (sim/) and the nearest triangle of a
// mesh (sva/base/triangle_tree.hpp) share it. Embree reports errors through a callback that may not throw (it is
// called from C); the message is kept per thread and turned into sva::Error by check() right after the call that
// raised it.
#include <memory>
#include <string>

struct RTCDeviceTy;
struct RTCSceneTy;

namespace sva::embree {

// Made on first use, then shared (Embree's devices are thread-safe). SVA_EMBREE_ISA (sse2, sse4.2, avx, avx2,
// avx512) forces Embree's kernels, so that one machine can show that no answer depends on them (tests/determinism);
// SVA_THREADS caps Embree's pool as it caps sva's. Throws sva::Error naming SVA_EMBREE_ISA when it names no ISA or
// one the CPU lacks.
RTCDeviceTy* device();

// Forgets an error this thread's earlier Embree calls left unchecked.
void clear_error();

// Throws sva::Error("<what>: Embree error <code>: <message>") when an Embree call on this thread reported an error
// since the last check or clear_error().
void check(const std::string& what);

// A committed scene, released with its owner (the search of triangle_tree.hpp).
struct SceneRelease {
  void operator()(RTCSceneTy* scene) const;
};
using Scene = std::unique_ptr<RTCSceneTy, SceneRelease>;

}  // namespace sva::embree
