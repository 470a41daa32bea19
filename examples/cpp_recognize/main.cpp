// cpp_recognize: load a map, stream one object's readings from a dataset file
// into a recognizer, print the hypotheses after every reading.
//
//   cpp_recognize MAP.svam DATA.svad [OBJECT [READINGS]]
//
// A robot stack does the same with readings from its sensor driver: one Engine
// per map (the device and the uploaded map), one Recognizer per object being
// touched, add_reading() per contact, estimate() whenever it needs an answer.
#include <sva/dataset.hpp>
#include <sva/engine.hpp>
#include <sva/error.hpp>
#include <sva/recognizer.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

void print_estimate(const sva::Estimate& e) {
  std::printf("after %zu readings: %s (p = %.3f)\n", e.readings, e.object_name.c_str(), e.object_probability[e.object]);
  for (const sva::PoseHypothesis& h : e.hypotheses) {
    // Standard deviations from the ROS-order covariance's diagonal: x, y, z (mm), rotations (rad).
    const auto sd = [&](int i) { return std::sqrt(h.covariance[i * 6 + i]); };
    std::printf("  %-12s mass %.3f  at (%7.1f %7.1f %7.1f) mm  +- (%.1f %.1f %.1f) mm, (%.2f %.2f %.2f) rad\n",
                h.object_name.c_str(), h.probability, h.pose.T.x, h.pose.T.y, h.pose.T.z, sd(0), sd(1), sd(2), sd(3),
                sd(4), sd(5));
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s MAP.svam DATA.svad [OBJECT [READINGS]]\n", argv[0]);
    return 2;
  }
  try {
    const sva::Map map = sva::Map::load(argv[1]);
    const sva::Dataset data = sva::load_dataset(argv[2]);
    const unsigned long object = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 0;
    const unsigned long wanted = argc > 4 ? std::strtoul(argv[4], nullptr, 10) : 10;
    if (object >= map.objects()) throw sva::Error("object " + std::to_string(object) + " is not in the map");

    // One engine per map: the backend (auto: a GPU where one is usable) and the map's upload, shared by every
    // recognizer made from it.
    const sva::Engine engine(map);
    std::printf("map '%s': %zu objects, backend %s\n", map.scene_name().c_str(), map.objects(),
                engine.backend_description().c_str());
    sva::Recognizer recognizer(engine, map.pose_space());

    unsigned long used = 0;
    for (const sva::Sample& sample : data.samples) {
      if (used == wanted) break;
      if (sample.object != object) continue;  // the dataset's ground truth picks one object's readings
      try {
        recognizer.add_reading(sample.reading);
      } catch (const sva::Error& e) {  // a contact that did not converge, or an image with nothing on it
        std::printf("skipped a reading: %s\n", e.what());
        continue;
      }
      ++used;
      print_estimate(recognizer.estimate(3));
    }
    if (used == 0) throw sva::Error("no usable reading of object " + std::to_string(object) + " in the dataset");
  } catch (const sva::Error& e) {
    std::fprintf(stderr, "cpp_recognize: %s\n", e.what());
    return 1;
  }
  return 0;
}
