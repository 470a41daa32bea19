#pragma once
// Sums fixed-point vote mass per pose-bin key: open addressing with a
// well-mixed hash, grown at half load. Integer sums do not depend on the order
// of the votes, so the sorted read-out is the same for any schedule.
#include <cstdint>
#include <vector>

namespace sva {

class BinAccumulator {
 public:
  explicit BinAccumulator(std::size_t expected = 1024);
  void add(std::uint64_t key, std::int64_t mass);
  std::size_t size() const { return size_; }
  // Touched keys in increasing order with their sums.
  void sorted(std::vector<std::uint64_t>* keys, std::vector<std::int64_t>* mass) const;
  void clear();

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  void grow();
  std::vector<std::uint64_t> keys_;
  std::vector<std::int64_t> mass_;
  std::size_t size_ = 0;
  std::size_t mask_ = 0;
};

}  // namespace sva
