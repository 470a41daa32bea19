// The single-session Recognizer: a batch of one, so that a robot's one session and an evaluation's thousand give
// the same answers by construction (the session table is recognition/batch_recognizer.cpp).
#include <sva/batch_recognizer.hpp>
#include <sva/recognizer.hpp>

#include <memory>
#include <span>

namespace sva {

struct Recognizer::Impl {
  BatchRecognizer batch;
};

Recognizer::Recognizer(const Map& map, const PoseSpaceSpec& pose_space, const RecognizerOptions& options)
    : impl_(std::make_unique<Impl>(Impl{BatchRecognizer(map, pose_space, 1, options)})) {}
Recognizer::Recognizer(const Engine& engine, const PoseSpaceSpec& pose_space, const RecognizerOptions& options)
    : impl_(std::make_unique<Impl>(Impl{BatchRecognizer(engine, pose_space, 1, options)})) {}
Recognizer::~Recognizer() = default;
Recognizer::Recognizer(Recognizer&&) noexcept = default;
Recognizer& Recognizer::operator=(Recognizer&&) noexcept = default;

void Recognizer::add_reading(const Reading& reading) {
  const std::size_t session = 0;
  impl_->batch.add_readings(std::span(&session, 1), std::span(&reading, 1));
}
Estimate Recognizer::estimate(std::size_t top_k, EstimateDepth depth) const {
  return impl_->batch.estimate(0, top_k, depth);
}
void Recognizer::set_prior(const Prior& prior) { impl_->batch.set_prior(0, prior); }
void Recognizer::save_session(const std::filesystem::path& file) const { impl_->batch.save_session(0, file); }
void Recognizer::restore_session(const std::filesystem::path& file) { impl_->batch.restore_session(0, file); }
void Recognizer::reset() { impl_->batch.reset(0); }
std::size_t Recognizer::reading_count() const { return impl_->batch.readings(0); }

}  // namespace sva
