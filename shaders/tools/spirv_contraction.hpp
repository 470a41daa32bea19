#pragma once
// A SPIR-V module's floating-point operations and their NoContraction
// decorations: what sva_spirv_embed (spirv_embed.cpp) completes and
// tests/shaders/test_spirv_embed.cpp checks in every embedded kernel.
#include <cstddef>
#include <cstdint>
#include <set>
#include <span>
#include <vector>

namespace sva::spirv {

constexpr std::uint32_t kMagic = 0x07230203u;
constexpr std::uint32_t kHeaderWords = 5;
constexpr std::uint32_t kOpDecorate = 71;
constexpr std::uint32_t kNoContraction = 42;

// Instructions whose result is a rounded floating-point operation that a
// compiler could contract (OpFNegate .. OpDot).
inline bool is_float_arithmetic(std::uint32_t op) {
  switch (op) {
    case 127:  // OpFNegate
    case 129:  // OpFAdd
    case 131:  // OpFSub
    case 133:  // OpFMul
    case 136:  // OpFDiv
    case 140:  // OpFRem
    case 141:  // OpFMod
    case 142:  // OpVectorTimesScalar
    case 143:  // OpMatrixTimesScalar
    case 144:  // OpVectorTimesMatrix
    case 145:  // OpMatrixTimesVector
    case 146:  // OpMatrixTimesMatrix
    case 147:  // OpOuterProduct
    case 148:  // OpDot
      return true;
    default:
      return false;
  }
}

// The module's layout puts annotations before the first type declaration:
// everything up to there is capabilities, entry points, debug names and
// decorations (logical layout, SPIR-V spec 2.4).
inline bool is_preamble(std::uint32_t op) {
  switch (op) {
    case 2: case 3: case 4: case 5: case 6: case 7: case 8:  // source, names, OpString, OpLine
    case 10: case 11: case 14: case 15: case 16: case 17:   // extensions, memory model, entry points, capabilities
    case 71: case 72: case 73: case 74: case 75:            // decorations
    case 317: case 330: case 331: case 332: case 5632: case 5633:
      return true;
    default:
      return false;
  }
}

struct Census {
  bool well_formed = false;
  std::set<std::uint32_t> decorated;        // ids decorated NoContraction
  std::vector<std::uint32_t> float_results;  // ids of float arithmetic results
  std::size_t first_type_word = 0;           // where annotations end: new decorations go before it
  std::size_t undecorated() const {
    std::size_t n = 0;
    for (std::uint32_t id : float_results) n += decorated.count(id) == 0;
    return n;
  }
};

inline Census census(std::span<const std::uint32_t> words) {
  Census c;
  if (words.size() < kHeaderWords || words[0] != kMagic) return c;
  for (std::size_t i = kHeaderWords; i < words.size();) {
    const std::uint32_t op = words[i] & 0xffffu, count = words[i] >> 16;
    if (count == 0 || i + count > words.size()) return c;
    if (op == kOpDecorate && count >= 3 && words[i + 2] == kNoContraction) c.decorated.insert(words[i + 1]);
    if (is_float_arithmetic(op) && count >= 3) c.float_results.push_back(words[i + 2]);
    if (c.first_type_word == 0 && !is_preamble(op)) c.first_type_word = i;
    i += count;
  }
  c.well_formed = c.first_type_word != 0;
  return c;
}

}  // namespace sva::spirv
