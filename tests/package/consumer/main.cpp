// Uses only installed headers: a scene from the installed assets, and the
// recognizer's error path for an empty map.
#include <sva/batch_recognizer.hpp>
#include <sva/error.hpp>
#include <sva/recognizer.hpp>
#include <sva/scene.hpp>

#include <cstdio>

int main() {
  const sva::Scene scene = sva::load_scene("paper3d");
  if (scene.objects.size() != 10) {
    std::fprintf(stderr, "expected 10 objects in the installed paper3d scene, got %zu\n", scene.objects.size());
    return 1;
  }
  try {
    sva::Recognizer r(sva::Map{}, scene.pose_space);
    std::fprintf(stderr, "an empty map was accepted\n");
    return 1;
  } catch (const sva::Error& e) {
    std::printf("ok: %zu objects; empty map refused: %s\n", scene.objects.size(), e.what());
  }
  return 0;
}
