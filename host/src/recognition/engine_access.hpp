#pragma once
// The one way into an Engine's shared state (recognition/engine.hpp): the public header only befriends this, so
// the recognizers made from an Engine reach its backend, device and surface index while users cannot.
#include <sva/engine.hpp>

#include <memory>

namespace sva {

struct EngineAccess {
  static const std::shared_ptr<Engine::Impl>& impl(const Engine& e) { return e.impl_; }
};

}  // namespace sva
