// The prefix code against independent answers: Huffman's cost (the sum of its merges' weights,
// computed here with a heap), Kraft's sum, and every code decoded back from random bits.
#include <algorithm>
#include <queue>

#include <catch2/catch.hpp>

#include "schemes/delta-dag/prefix_code.h"
#include "schemes/interface/splitmix.h"

namespace sb {
namespace {

using namespace delta_dag;

// The bits an optimal prefix code spends on these counts: the sum of every merge's weight.
uint64_t huffmanCost(const std::vector<uint64_t>& counts) {
  std::priority_queue<uint64_t, std::vector<uint64_t>, std::greater<>> heap(counts.begin(),
                                                                            counts.end());
  uint64_t cost = 0;
  while (heap.size() > 1) {
    const uint64_t a = heap.top();
    heap.pop();
    const uint64_t b = heap.top();
    heap.pop();
    cost += a + b;
    heap.push(a + b);
  }
  return counts.size() == 1 ? counts[0] : cost;
}

uint64_t costOf(const std::vector<uint64_t>& counts, const std::vector<uint8_t>& lengths) {
  uint64_t cost = 0;
  for (size_t s = 0; s < counts.size(); ++s) cost += counts[s] * lengths[s];
  return cost;
}

std::vector<uint64_t> randomCounts(uint64_t& random, size_t n, bool skewed) {
  std::vector<uint64_t> counts(n);
  for (uint64_t& count : counts)
    count = skewed ? uint64_t(1) << nextRandom(random) % 40 : 1 + nextRandom(random) % 1000;
  return counts;
}

TEST_CASE("unlimited lengths are Huffman's: optimal cost", "[delta-dag][prefix-code]") {
  uint64_t random = 7;
  for (int trial = 0; trial < 300; ++trial) {
    const std::vector<uint64_t> counts = randomCounts(random, 1 + nextRandom(random) % 200, false);
    const std::vector<uint8_t> lengths = huffmanLengths(counts, kMaxCodeBits);
    CHECK(isPrefixCode(lengths, kMaxCodeBits));
    CHECK(costOf(counts, lengths) == huffmanCost(counts));
  }
}

TEST_CASE("limited lengths fit, and cost no less than Huffman's", "[delta-dag][prefix-code]") {
  uint64_t random = 11;
  for (int trial = 0; trial < 300; ++trial) {
    const uint32_t maxBits = 4 + uint32_t(nextRandom(random) % 9);
    const size_t n = 1 + nextRandom(random) % (size_t(1) << maxBits);
    const std::vector<uint64_t> counts = randomCounts(random, n, true);
    const std::vector<uint8_t> lengths = huffmanLengths(counts, maxBits);
    REQUIRE(isPrefixCode(lengths, maxBits));
    CHECK(costOf(counts, lengths) >= huffmanCost(counts));
  }
  // 2^maxBits symbols fill the code: every length is maxBits.
  const std::vector<uint8_t> full = huffmanLengths(randomCounts(random, 256, true), 8);
  CHECK(std::all_of(full.begin(), full.end(), [](uint8_t length) { return length == 8; }));
  CHECK_THROWS(huffmanLengths(std::vector<uint64_t>(257, 1), 8));
}

TEST_CASE("the decode table reads back every code from any bits after it",
          "[delta-dag][prefix-code]") {
  uint64_t random = 13;
  for (int trial = 0; trial < 100; ++trial) {
    const uint32_t maxBits = 1 + uint32_t(nextRandom(random) % 12);
    const size_t n = 1 + nextRandom(random) % (size_t(1) << maxBits);
    const std::vector<uint8_t> lengths = huffmanLengths(randomCounts(random, n, true), maxBits);
    const std::vector<uint32_t> codes = canonicalCodes(lengths);
    const std::vector<uint16_t> table = decodeTable(lengths, maxBits);
    for (size_t s = 0; s < n; ++s)
      for (int tail = 0; tail < 4; ++tail) {
        const uint64_t bits = codes[s] | nextRandom(random) << lengths[s];
        CHECK(table[bits & ((uint64_t(1) << maxBits) - 1)] == s);
      }
  }
  // An incomplete code leaves entries that no code starts.
  const std::vector<uint16_t> table = decodeTable({1, 2}, 2);
  CHECK(std::count(table.begin(), table.end(), kNoSymbol) == 1);
  CHECK_FALSE(isPrefixCode({1, 1, 2}, 2));
  CHECK_FALSE(isPrefixCode({0}, 2));
}

}  // namespace
}  // namespace sb
