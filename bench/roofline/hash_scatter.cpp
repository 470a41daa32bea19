#include "roofline/hash_scatter.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cstring>
#include <map>

#include <sva/error.hpp>

#include "spv/hash_scatter.h"
#include "votes/bin_hash.hpp"
#include "votes/fixed_point.hpp"

namespace sva::bench {

namespace {

struct Push {
  std::uint32_t count, capacity;
};
}  // namespace

HashScatter::HashScatter(vk::Context& context, std::size_t initial_capacity)
    : ctx_(context),
      pipeline_(context.create_pipeline("hash_scatter", sva_spv_hash_scatter, 5, sizeof(Push))),
      capacity_(std::bit_ceil(std::max<std::size_t>(initial_capacity, 64))) {
  // 12 bytes per vote (key + weight); stay well under the binding limit.
  const std::size_t by_range = context.info().max_storage_buffer_range / sizeof(std::uint64_t);
  const std::size_t by_groups = static_cast<std::size_t>(context.info().max_workgroup_count_x) * SVA_WORKGROUP_SIZE;
  max_chunk_ = std::min({by_range, by_groups, std::size_t{1} << 22});
}

std::vector<std::pair<std::uint64_t, std::int64_t>> HashScatter::run(std::span<const std::uint64_t> keys,
                                                                     std::span<const float> weights) {
  assert(keys.size() == weights.size());
  assert(std::none_of(keys.begin(), keys.end(), [](std::uint64_t k) { return k == hash::kEmptyKey; }));
  const std::size_t chunk = std::max<std::size_t>(1, std::min(max_chunk_, keys.size()));
  vk::Buffer key_buf = ctx_.create_buffer(chunk * sizeof(std::uint64_t));
  vk::Buffer weight_buf = ctx_.create_buffer(chunk * sizeof(float));
  vk::Buffer status = ctx_.create_buffer(sizeof(std::uint32_t));
  for (;;) {
    kernel_ms_ = 0.0;
    // The table must fit one binding too; a histogram that large is a caller error.
    if (capacity_ * sizeof(std::int64_t) > ctx_.info().max_storage_buffer_range)
      throw Error("GPU vote table would exceed the device's storage-buffer range (" + std::to_string(capacity_) +
                  " slots)");
    vk::Buffer table_keys = ctx_.create_buffer(capacity_ * sizeof(std::uint64_t));
    vk::Buffer table_sums = ctx_.create_buffer(capacity_ * sizeof(std::int64_t));
    std::memset(table_keys.data(), 0xff, table_keys.size());
    *status.as<std::uint32_t>() = 0;
    for (std::size_t begin = 0; begin < keys.size(); begin += chunk) {
      const std::size_t n = std::min(chunk, keys.size() - begin);
      std::memcpy(key_buf.data(), keys.data() + begin, n * sizeof(std::uint64_t));
      std::memcpy(weight_buf.data(), weights.data() + begin, n * sizeof(float));
      Push push{static_cast<std::uint32_t>(n), static_cast<std::uint32_t>(capacity_)};
      std::vector<std::uint8_t> pb(sizeof push);
      std::memcpy(pb.data(), &push, sizeof push);
      std::vector<double> ms;
      ctx_.run({{&pipeline_,
                 {&key_buf, &weight_buf, &table_keys, &table_sums, &status},
                 pb,
                 static_cast<std::uint32_t>((n + SVA_WORKGROUP_SIZE - 1) / SVA_WORKGROUP_SIZE)}},
               &ms);
      for (double m : ms) kernel_ms_ += m;
      if (*status.as<std::uint32_t>() != 0) break;
    }
    if (*status.as<std::uint32_t>() != 0) {
      capacity_ *= 2;  // overflow: nothing partial is kept; grow and scatter everything again
      ++grows_;
      continue;
    }
    std::vector<std::pair<std::uint64_t, std::int64_t>> out;
    const auto* tk = table_keys.as<std::uint64_t>();
    const auto* ts = table_sums.as<std::int64_t>();
    for (std::size_t s = 0; s < capacity_; ++s)
      if (tk[s] != hash::kEmptyKey) out.emplace_back(tk[s], ts[s]);
    std::sort(out.begin(), out.end());
    return out;
  }
}

std::vector<std::pair<std::uint64_t, std::int64_t>> scatter_reference(std::span<const std::uint64_t> keys,
                                                                      std::span<const float> weights) {
  std::map<std::uint64_t, std::int64_t> sums;
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (auto units = to_fixed(weights[i]); units != 0) sums[keys[i]] += units;
  return {sums.begin(), sums.end()};
}

}  // namespace sva::bench
