#include <sva/eval/speed_run.hpp>

#include <sva/batch_recognizer.hpp>
#include <sva/prior.hpp>

#include <algorithm>
#include <chrono>
#include <map>
#include <numbers>
#include <string>

#include <nlohmann/json.hpp>
#include <sva/base/parallel.hpp>
#include <sva/base/progress.hpp>
#include <sva/eval/evaluation.hpp>
#include <sva/eval/trials.hpp>
#include "bench/gpu_model.hpp"
#include "eval/metrics.hpp"
#include "recognition/lockstep.hpp"
#include "roofline/roofline.hpp"

namespace sva::bench {

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

// What one update of a group of sessions cast and cost.
struct StepFigures {
  std::size_t sessions = 0;
  std::uint64_t votes = 0, votes_zero = 0;
  double seconds = 0.0, estimate_seconds = 0.0;
  std::uint64_t estimate_submissions = 0;  // device round trips of the sessions' estimates (0 on the CPU)
  std::uint64_t update_submissions = 0;    // of the update since the last estimate (a group's first: its resets too)
  // Device memory allocations of the estimates, and of the update (0 on the CPU).
  std::uint64_t estimate_allocations = 0, update_allocations = 0;
  BatchRecognizer::EstimateTiming estimate_stages;  // where the estimates' time went, summed over the sessions
  std::vector<double> belief_bytes;                 // per session of the update, after it
};

// The figures at one reading count, over all groups.
struct Checkpoint {
  std::vector<double> update_ms;  // per group update, divided by its sessions (per session-update)
  std::uint64_t votes = 0, votes_zero = 0;
  std::size_t session_updates = 0;
  double seconds = 0.0;
  std::size_t correct = 0, trials = 0;
  std::vector<double> translation_mm;
  std::vector<double> kernel_ms, backend_host_ms, fold_ms, belief_growth_ms;
  // A device update's time by part (update_split_json), each update's own: the device between its kernels, the wait
  // past the device's span, recording the submissions, the host outside them.
  std::vector<double> between_kernels_ms, wait_past_ms, record_ms, outside_ms;
  // The device's time by kernel (kernel_by_pipeline_json), summed over the updates it timed, and their count.
  std::map<std::string, BatchRecognizer::KernelTime> by_pipeline;
  std::size_t timed_updates = 0;
  std::vector<double> estimate_ms;           // per session: object, refined pose and top-1 after the update
  std::vector<double> estimate_submissions;  // per session: the device round trips of its estimate (a batch's share)
  std::vector<double> update_submissions;    // per session: the device round trips of its update (a batch's share)
  std::vector<double> estimate_allocations, update_allocations;  // per session: device memory allocations, likewise
  // Per session: each stage's ms of its estimate (the sessions' sum divided by them; BatchRecognizer::EstimateTiming).
  std::vector<double> stage_belief_ms, stage_fit_ms, stage_verify_ms, stage_posterior_ms;
  BatchRecognizer::Work work;        // summed over the checkpoint's updates (all sessions of each)
  std::vector<double> belief_bytes;  // per session after its update: a live session's memory
};

double ratio(double a, double b) { return b > 0 ? a / b : 0.0; }
double ratio(std::uint64_t a, std::uint64_t b) { return ratio(static_cast<double>(a), static_cast<double>(b)); }

// Bytes a unit of counted work moves (docs/recognition.md, "Work counted"): a map entry (reading a, reading b,
// weight), an aligned match's two training contacts (position, normal, normConf), a hash slot (key and value).
constexpr double kEntryBytes = 12.0, kMatchBytes = 2 * 28.0, kSlotBytes = 16.0;

// The work per session-update at a checkpoint, and the bytes it implies; null where the backend counts nothing.
// A device counts its vote tables' atomics, not its belief probes (null).
json work_json(const BatchRecognizer::Work& w, std::size_t updates, bool device) {
  if (w.entries == 0 && w.table_probes == 0) return nullptr;
  const auto per = [&](std::uint64_t v) { return ratio(static_cast<double>(v), static_cast<double>(updates)); };
  return {{"pairs", per(w.pairs)},
          {"map_entries", per(w.entries)},
          {"matches", per(w.matches)},
          {"votes", per(w.votes)},
          {"vote_table_probes", per(w.table_probes)},
          {"bins", per(w.bins)},
          {"belief_probes", device ? json(nullptr) : json(per(w.belief_probes))},
          {"vote_table_atomics", device ? json(per(w.atomics)) : json(nullptr)},
          {"bytes",
           {{"map", per(w.entries) * kEntryBytes + per(w.matches) * kMatchBytes},
            {"vote_tables", per(w.table_probes) * kSlotBytes},
            // A device does not count its belief probes: at least one per bin.
            {"fold", (per(w.bins) + std::max(per(w.belief_probes), device ? per(w.bins) : 0.0)) * kSlotBytes}}}};
}

json median_or_null(const std::vector<double>& v) {
  const auto m = eval::median(v);
  return m ? json(*m) : json(nullptr);
}

void record_checkpoint(Checkpoint& c, const BatchRecognizer& rec, const std::vector<eval::Trial>& tr,
                       const std::vector<Estimate>& est, const StepFigures& f) {
  const auto n = static_cast<double>(f.sessions);
  c.update_ms.push_back(1e3 * f.seconds / n);
  c.estimate_ms.push_back(1e3 * f.estimate_seconds / n);
  c.estimate_submissions.push_back(static_cast<double>(f.estimate_submissions) / n);
  c.update_submissions.push_back(static_cast<double>(f.update_submissions) / n);
  c.estimate_allocations.push_back(static_cast<double>(f.estimate_allocations) / n);
  c.update_allocations.push_back(static_cast<double>(f.update_allocations) / n);
  const BatchRecognizer::EstimateTiming& st = f.estimate_stages;
  if (st.sessions > 0) {
    const auto per = static_cast<double>(st.sessions);
    c.stage_belief_ms.push_back(st.belief_ms / per);
    c.stage_fit_ms.push_back(st.fit_ms / per);
    c.stage_verify_ms.push_back(st.verify_ms / per);
    c.stage_posterior_ms.push_back(st.posterior_ms / per);
  }
  c.votes += f.votes;
  c.votes_zero += f.votes_zero;
  c.belief_bytes.insert(c.belief_bytes.end(), f.belief_bytes.begin(), f.belief_bytes.end());
  c.session_updates += f.sessions;
  c.seconds += f.seconds;
  const auto t = rec.last_backend_timing();
  c.kernel_ms.push_back(t.kernel_ms);
  c.backend_host_ms.push_back(t.host_ms);
  c.fold_ms.push_back(t.fold_ms);
  c.belief_growth_ms.push_back(t.belief_growth_ms);
  c.record_ms.push_back(t.record_ms);
  c.outside_ms.push_back(std::max(0.0, t.kernel_ms + t.host_ms - t.record_ms - t.wait_ms));  // two clocks: never < 0
  if (t.device_span_ms > 0.0) {  // the device has timestamps
    c.between_kernels_ms.push_back(std::max(0.0, t.device_span_ms - t.kernel_ms));
    c.wait_past_ms.push_back(std::max(0.0, t.wait_ms - t.device_span_ms));
    ++c.timed_updates;
    for (const auto& [name, k] : t.kernel_ms_by_pipeline) {
      c.by_pipeline[name].ms += k.ms;
      c.by_pipeline[name].dispatches += k.dispatches;
    }
  }
  const BatchRecognizer::Work w = rec.last_update_work();
  for (auto [sum, v] : {std::pair{&c.work.pairs, w.pairs},
                        {&c.work.entries, w.entries},
                        {&c.work.matches, w.matches},
                        {&c.work.votes, w.votes},
                        {&c.work.table_probes, w.table_probes},
                        {&c.work.bins, w.bins},
                        {&c.work.belief_probes, w.belief_probes},
                        {&c.work.atomics, w.atomics}})
    *sum += v;
  for (std::size_t i = 0; i < est.size(); ++i) {
    ++c.trials;
    if (est[i].object != tr[i].object) continue;
    ++c.correct;
    if (est[i].pose_valid) c.translation_mm.push_back(glm::length(est[i].pose.T - tr[i].pose.T));
  }
}

// A device update's time by part, each the median over the checkpoint's updates (ms per submission of its
// sessions): the kernels; the device between them (barriers, fills, copies: its span less the kernels); the wait
// past the device's span (submitting, the fence, untimed transfers); recording the submissions; and the host's work
// outside them (of which the beliefs' growth). One update's parts sum to its time. Null on the CPU; the parts that
// need the device's timestamps, the kernels too, are null without them.
json update_split_json(const Checkpoint& c, bool device) {
  if (!device || c.kernel_ms.empty()) return nullptr;
  // Untimed (no timestamps, or SVA_VK_TIMESTAMPS=0): the kernels are in no part, not 0 ms; the host's parts hold them.
  return {{"kernels", c.timed_updates > 0 ? median_or_null(c.kernel_ms) : json(nullptr)},
          {"device_between_kernels", median_or_null(c.between_kernels_ms)},
          {"wait_past_device", median_or_null(c.wait_past_ms)},
          {"recording", median_or_null(c.record_ms)},
          {"host_outside_submissions", median_or_null(c.outside_ms)},
          {"belief_growth", median_or_null(c.belief_growth_ms)}};
}

// A device update's time by kernel: per pipeline (named by its shader: the votes, the fold, the estimate's passes,
// a table's move), its GPU ms and dispatches per update (per submission of its sessions), each the mean over the
// checkpoint's updates rather than the median, so that a rare pass (a growth) shows and the names sum to the
// kernels' mean. Null on the CPU and where the device has no timestamps.
json kernel_by_pipeline_json(const Checkpoint& c, bool device) {
  if (!device || c.timed_updates == 0) return nullptr;
  const auto n = static_cast<double>(c.timed_updates);
  json out = json::object();
  for (const auto& [name, k] : c.by_pipeline)
    out[name] = {{"ms", k.ms / n}, {"dispatches", static_cast<double>(k.dispatches) / n}};
  return out;
}

json checkpoint_json(std::size_t readings, const Checkpoint& c, bool device, std::size_t sessions) {
  const json work = work_json(c.work, c.session_updates, device);
  return {
      {"readings", readings},
      {"update_ms", median_or_null(c.update_ms)},
      {"votes_per_update", ratio(static_cast<double>(c.votes), static_cast<double>(c.trials))},
      {"votes_per_second", ratio(static_cast<double>(c.votes), c.seconds)},
      {"session_updates_per_second", ratio(static_cast<double>(c.session_updates), c.seconds)},
      {"votes_zero_per_update", ratio(static_cast<double>(c.votes_zero), static_cast<double>(c.trials))},
      {"votes_zero_fraction", ratio(c.votes_zero, c.votes)},
      {"gpu_kernel_ms", median_or_null(c.kernel_ms)},
      {"backend_host_ms", median_or_null(c.backend_host_ms)},
      {"backend_belief_growth_ms", median_or_null(c.belief_growth_ms)},
      {"gpu_fold_ms", median_or_null(c.fold_ms)},
      {"update_split_ms", update_split_json(c, device)},
      {"kernel_ms_by_pipeline", kernel_by_pipeline_json(c, device)},
      {"estimate_ms", median_or_null(c.estimate_ms)},
      {"estimate_device_submissions", device ? median_or_null(c.estimate_submissions) : json(nullptr)},
      {"update_device_submissions", device ? median_or_null(c.update_submissions) : json(nullptr)},
      {"estimate_device_allocations", device ? median_or_null(c.estimate_allocations) : json(nullptr)},
      {"update_device_allocations", device ? median_or_null(c.update_allocations) : json(nullptr)},
      {"estimate_stage_ms",
       {{"belief", median_or_null(c.stage_belief_ms)},
        {"fits", median_or_null(c.stage_fit_ms)},
        {"verify", median_or_null(c.stage_verify_ms)},
        {"posterior", median_or_null(c.stage_posterior_ms)}}},
      {"accuracy", ratio(static_cast<double>(c.correct), static_cast<double>(c.trials))},
      {"translation_error_mm", median_or_null(c.translation_mm)},
      {"work_per_update", work},
      {"gpu_model", bench::model_update(work, bench::h100_sxm(), sessions)},
      {"belief_bytes_per_session", median_or_null(c.belief_bytes)},
      {"belief_bytes_per_session_max",
       c.belief_bytes.empty() ? json(nullptr) : json(*std::max_element(c.belief_bytes.begin(), c.belief_bytes.end()))}};
}

// Host memory of the run and the device memory its backend holds. A device
// backend that does not report its memory yet gives null, not 0 bytes.
json memory_json(const RunMemory& m, const BatchRecognizer& rec) {
  const BatchRecognizer::DeviceMemory d = rec.device_memory();
  const bool cpu = rec.backend() == BackendKind::cpu;
  auto device = [&](std::uint64_t bytes) { return cpu || bytes > 0 ? json(bytes) : json(nullptr); };
  return {{"peak_rss_bytes", m.process_peak_bytes},
          {"rss_before_bytes", m.rss_before_bytes},
          {"rss_after_bytes", m.rss_after_bytes},
          {"rss_increase_bytes", m.rss_increase_bytes()},
          {"peak_rss_during_bytes", m.peak_during_bytes ? json(*m.peak_during_bytes) : json(nullptr)},
          {"device_bytes", device(d.bytes)},
          {"map_device_bytes", device(d.map_bytes)},
          {"device_held_bytes", device(d.held_bytes)}};
}

// Steps the trials through the recognizer and keeps the figures of every
// update and of the checkpoints.
class SpeedRecorder {
 public:
  SpeedRecorder(BatchRecognizer& rec, const std::vector<std::size_t>& checkpoints, std::size_t top_k,
                EstimateDepth depth)
      : rec_(rec),
        checkpoints_(checkpoints),
        top_k_(top_k),
        depth_(depth),
        sessions_(rec.sessions()),
        after_last_(device_counts()) {}

  void on_step(const LockstepStep& s, const std::vector<eval::Trial>& tr) {
    StepFigures f;
    f.sessions = s.sessions.size();
    f.seconds = s.update_ms / 1e3;
    std::vector<Estimate> est;
    const auto t1 = Clock::now();
    const DeviceCounts updated = device_counts();
    f.update_submissions = updated.submissions - after_last_.submissions;
    f.update_allocations = updated.allocations - after_last_.allocations;
    est = rec_.estimates(s.sessions, top_k_, depth_);
    after_last_ = device_counts();
    f.estimate_submissions = after_last_.submissions - updated.submissions;
    f.estimate_allocations = after_last_.allocations - updated.allocations;
    f.estimate_stages = rec_.last_estimate_timing();
    for (const Estimate& e : est) {
      f.votes += e.votes;
      f.votes_zero += e.votes_zero;
    }
    f.estimate_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
    all_.votes += f.votes;
    all_.votes_zero += f.votes_zero;
    all_.sessions += f.sessions;
    all_.seconds += f.seconds;
    all_.estimate_seconds += f.estimate_seconds;
    const std::size_t readings = s.step + 1;
    if (!std::binary_search(checkpoints_.begin(), checkpoints_.end(), readings)) return;
    for (std::size_t i : s.sessions) f.belief_bytes.push_back(static_cast<double>(rec_.belief_bytes(i)));
    record_checkpoint(cp_[readings], rec_, tr, est, f);
  }

  // The run's totals and its curve (without backend, device and memory).
  json figures() const {
    json j = {{"votes_per_second", ratio(static_cast<double>(all_.votes), all_.seconds)},
              {"session_updates_per_second", ratio(static_cast<double>(all_.sessions), all_.seconds)},
              // With the estimate after each update, run one after the other as here: what a study that asks an
              // answer after every reading gets from one recognizer (issue 52's batch goal counts both).
              {"session_updates_with_estimates_per_second",
               ratio(static_cast<double>(all_.sessions), all_.seconds + all_.estimate_seconds)},
              {"votes", all_.votes},
              {"votes_zero", all_.votes_zero},
              {"votes_zero_fraction", ratio(all_.votes_zero, all_.votes)}};
    json points = json::array();
    const bool device = rec_.backend() != BackendKind::cpu;
    for (const auto& [readings, c] : cp_) points.push_back(checkpoint_json(readings, c, device, sessions_));
    j["curve"] = points;
    return j;
  }

 private:
  BatchRecognizer& rec_;
  const std::vector<std::size_t>& checkpoints_;
  std::size_t top_k_;    // hypotheses per estimate (SpeedRunSpec::top_k)
  EstimateDepth depth_;  // SpeedRunSpec::estimate
  std::map<std::size_t, Checkpoint> cp_;
  // The device's round trips and memory allocations so far.
  struct DeviceCounts {
    std::uint64_t submissions = 0, allocations = 0;
  };
  DeviceCounts device_counts() const { return {rec_.device_submissions(), rec_.device_allocations()}; }

  std::size_t sessions_;     // per submission
  DeviceCounts after_last_;  // the device's counts after the last step's estimates
  StepFigures all_;          // every update of the run; sessions = session-updates
};

// The prior of a trial's session: every object of the map at the trial's true pose (BenchPosePrior).
Prior prior_of(const eval::Trial& t, const BenchPosePrior& p, std::size_t objects) {
  PosePrior g;
  g.position = t.pose.T;
  g.position_sigma_mm = p.position_sigma_mm;
  g.has_rotation = p.rotation_sigma_deg > 0.0;
  g.rotation = t.pose.R;
  g.rotation_sigma_rad = p.rotation_sigma_deg * std::numbers::pi / 180.0;
  Prior out;
  out.object_pose.assign(objects, g);
  return out;
}

json pose_prior_json(const BenchPosePrior& p) {
  if (!p.on()) return nullptr;
  return {{"position_sigma_mm", p.position_sigma_mm},
          {"rotation_sigma_deg", p.rotation_sigma_deg > 0.0 ? json(p.rotation_sigma_deg) : json(nullptr)}};
}

// The lock-step hooks of a run's trials: each group's trials made into *tr (alive until the next group) and, with a
// camera's prior, each session's prior at its trial's true pose.
LockstepHooks trial_hooks(BatchRecognizer& rec, eval::TrialGenerator& gen, const SpeedRunSpec& spec,
                          std::size_t objects, std::vector<eval::Trial>* tr) {
  LockstepHooks hooks;
  hooks.group = [&gen, tr](std::size_t first, std::size_t count) {
    tr->clear();
    std::vector<std::span<const Reading>> readings;
    for (std::size_t i = 0; i < count; ++i) tr->push_back(gen.make(first + i));
    for (const auto& t : *tr) readings.emplace_back(t.readings);
    return readings;
  };
  if (spec.pose_prior.on())
    hooks.on_group_start = [&rec, tr, prior = spec.pose_prior, objects](std::size_t, std::size_t count) {
      for (std::size_t i = 0; i < count; ++i) rec.set_prior(i, prior_of((*tr)[i], prior, objects));
    };
  return hooks;
}

// SpeedRunSpec::warm: the first group's trials stepped to the end with the run's estimates, nothing recorded.
void warm_up(BatchRecognizer& rec, eval::TrialGenerator& gen, const SpeedRunSpec& spec, std::size_t objects) {
  const std::size_t count = rec.sessions();
  util::Progress progress(spec.label + " warm-up", count * spec.checkpoints.back());
  std::vector<eval::Trial> tr;
  LockstepHooks hooks = trial_hooks(rec, gen, spec, objects, &tr);
  hooks.progress = &progress;
  hooks.on_step = [&](const LockstepStep& s) { rec.estimates(s.sessions, spec.top_k, spec.estimate); };
  run_lockstep(rec, count, hooks);
  progress.finish();
}

}  // namespace

json run_speed(const Map& map, const Dataset& test, const SpeedRunSpec& spec, MemoryMeter& meter) {
  const std::size_t max_readings = spec.checkpoints.back();
  eval::TrialGenerator gen(test, map.pose_space(), spec.seed, max_readings);
  RecognizerOptions ro;
  ro.backend = spec.backend;
  ro.vulkan_device = spec.vulkan_device;
  ro.refine_pose = spec.refine_pose;
  ro.surface_check = spec.surface_check;
  ro.max_pairs_per_update = spec.max_pairs_per_update;
  ro.likelihood_cutoff = spec.likelihood_cutoff;
  ro.belief_budget_bins = spec.belief_budget_bins;
  meter.start();
  util::Progress progress(spec.label, spec.trials * max_readings);
  BatchRecognizer rec(map, map.pose_space(), std::min(spec.sessions, spec.trials), ro);
  if (spec.warm) warm_up(rec, gen, spec, map.objects());
  SpeedRecorder recorder(rec, spec.checkpoints, spec.top_k, spec.estimate);
  std::vector<eval::Trial> tr;
  LockstepHooks hooks = trial_hooks(rec, gen, spec, map.objects(), &tr);
  hooks.progress = &progress;
  hooks.on_step = [&](const LockstepStep& s) { recorder.on_step(s, tr); };
  run_lockstep(rec, spec.trials, hooks);
  progress.finish();
  const RunMemory memory = meter.stop();
  json j = {{"backend", eval::backend_name(spec.backend)},
            {"device", rec.backend_description()},
            {"sessions_per_submission", spec.sessions},
            {"trials", spec.trials},
            {"max_pairs_per_update", spec.max_pairs_per_update},
            {"likelihood_cutoff", spec.likelihood_cutoff},
            {"belief_budget_bins", spec.belief_budget_bins},
            {"top_k", spec.top_k},
            {"refine_pose", spec.refine_pose},
            {"surface_check", spec.surface_check},
            {"estimate", estimate_depth_name(spec.estimate)},
            {"pose_prior", pose_prior_json(spec.pose_prior)},
            {"warm", spec.warm}};
  j.update(recorder.figures());
  j["memory"] = memory_json(memory, rec);
  return j;
}

json roofline_json(std::size_t votes, std::size_t bins, const std::string& device) {
  const Roofline r = measure_roofline(votes, bins, device);
  json j = {{"device", r.device},
            {"votes", r.votes},
            {"bins", r.bins},
            {"kernel_ms", r.kernel_ms},
            {"votes_per_second", r.votes_per_second}};
  if (r.hash_kernel_ms > 0) {
    j["hash_kernel_ms"] = r.hash_kernel_ms;
    j["hash_votes_per_second"] = r.hash_votes_per_second;
  }
  const VoteMathRoofline& m = r.vote_math;
  const auto per_second = [](double v) { return v > 0 ? json(v) : json(nullptr); };  // null without timestamps
  j["vote_math"] = {{"matches", m.matches},
                    {"samples", m.samples},
                    {"exact_agrees_with_cpu", m.exact_agrees},
                    {"exact_samples_per_second", per_second(m.exact_samples_per_second())},
                    {"device_division_samples_per_second", per_second(m.device_division_samples_per_second())}};
  const HostReads& h = r.host_reads;
  j["host_reads"] = {{"loads", h.loads},
                     {"mapped_ns_per_load", h.mapped_ns_per_load},
                     {"readback_ns_per_load", h.readback_ns_per_load},
                     {"mapped_device_local", h.mapped_device_local},
                     {"sums_agree", h.sums_agree}};
  return j;
}

namespace {

nlohmann::json run_all(const Map& map, const Dataset& test, const BenchPlan& plan, MemoryMeter& meter) {
  nlohmann::json runs = nlohmann::json::array();
  for (BackendKind backend : plan.backends) {
    SpeedRunSpec spec;
    spec.backend = backend;
    spec.trials = plan.trials;
    spec.checkpoints = plan.checkpoints;
    spec.seed = plan.seed;
    spec.vulkan_device = plan.device;
    spec.refine_pose = plan.refine_pose;
    spec.surface_check = plan.surface_check;
    spec.estimate = plan.estimate;
    spec.max_pairs_per_update = plan.max_pairs_per_update;
    spec.likelihood_cutoff = plan.likelihood_cutoff;
    spec.belief_budget_bins = plan.belief_budget_bins;
    spec.top_k = plan.top_k;
    spec.pose_prior = plan.pose_prior;
    spec.warm = plan.warm;
    spec.label = eval::backend_name(backend);
    runs.push_back(run_speed(map, test, spec, meter));
    if (plan.batch <= 1) continue;
    // At least `batch` trials, so the first group fills the batch.
    spec.trials = std::max(plan.trials, plan.batch);
    spec.sessions = plan.batch;
    spec.label += " batch";
    runs.push_back(run_speed(map, test, spec, meter));
  }
  return runs;
}

const nlohmann::json* find_run(const nlohmann::json& runs, const std::string& backend, std::size_t sessions) {
  for (const auto& r : runs)
    if (r["backend"] == backend && r["sessions_per_submission"].get<std::size_t>() == sessions) return &r;
  return nullptr;
}

// Per reading count, a run's time per update against another run's: the CPU reference's single session
// (speedup_vs_cpu, every non-CPU run) and the CPU batch of the same size (speedup_vs_cpu_batch, batched runs).
void add_speedups(nlohmann::json& runs) {
  const nlohmann::json cpu = runs;  // the references, unchanged while the runs get their ratios
  for (auto& r : runs) {
    if (r["backend"] == "cpu") continue;
    const std::size_t sessions = r["sessions_per_submission"].get<std::size_t>();
    const nlohmann::json* single = find_run(cpu, "cpu", 1);
    const nlohmann::json* batch = sessions > 1 ? find_run(cpu, "cpu", sessions) : nullptr;
    for (std::size_t i = 0; i < r["curve"].size(); ++i) {
      auto& p = r["curve"][i];
      if (p["update_ms"].is_null() || p["update_ms"].get<double>() <= 0) continue;
      const double ms = p["update_ms"].get<double>();
      auto ratio_to = [&](const nlohmann::json* ref, const char* key) {
        if (ref && i < (*ref)["curve"].size() && !(*ref)["curve"][i]["update_ms"].is_null())
          p[key] = (*ref)["curve"][i]["update_ms"].get<double>() / ms;
      };
      ratio_to(single, "speedup_vs_cpu");
      ratio_to(batch, "speedup_vs_cpu_batch");
    }
  }
}

}  // namespace

nlohmann::json run_bench(const Map& map, const Dataset& test, const BenchPlan& plan) {
  nlohmann::json out = {
      {"scene", map.scene_name()}, {"map_entries", map.entries()}, {"threads", util::default_threads()}};
  MemoryMeter meter;  // one for the process: it keeps the peak across the runs' resets
  out["runs"] = run_all(map, test, plan, meter);
  if (std::find(plan.backends.begin(), plan.backends.end(), BackendKind::vulkan) != plan.backends.end())
    out["roofline"] = roofline_json(plan.roofline_votes, 1 << 20, plan.device);
  out["peak_rss_bytes"] = meter.process_peak_bytes();
  add_speedups(out["runs"]);
  if (out.contains("roofline")) {
    const double roof = out["roofline"]["votes_per_second"].get<double>();
    for (auto& r : out["runs"])
      if (r["backend"] == "vulkan") r["fraction_of_roofline"] = r["votes_per_second"].get<double>() / roof;
  }
  return out;
}

}  // namespace sva::bench
