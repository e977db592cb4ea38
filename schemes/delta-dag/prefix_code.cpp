#include "schemes/delta-dag/prefix_code.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace sb::delta_dag {

std::vector<uint8_t> huffmanLengths(const std::vector<uint64_t>& counts, uint32_t maxBits) {
  const size_t n = counts.size();
  if (n == 0 || maxBits == 0 || maxBits > kMaxCodeBits || n > (size_t(1) << maxBits))
    throw std::invalid_argument("huffmanLengths: no code of that many symbols and bits");
  if (n == 1) return {1};
  // Huffman's merges with two queues: the leaves by count, then the merged nodes as made (their
  // counts never decrease). Node i < n is the i-th leaf by count; n + m the m-th merge.
  std::vector<uint32_t> byCount(n);
  std::iota(byCount.begin(), byCount.end(), 0u);
  std::stable_sort(byCount.begin(), byCount.end(),
                   [&](uint32_t a, uint32_t b) { return counts[a] < counts[b]; });
  std::vector<uint64_t> weight(2 * n - 1);
  std::vector<uint32_t> parent(2 * n - 1, 0);
  for (size_t i = 0; i < n; ++i) weight[i] = counts[byCount[i]];
  size_t leaf = 0, merged = n;
  const auto take = [&](size_t made) {
    const bool fromLeaves = leaf < n && (merged == made || weight[leaf] <= weight[merged]);
    return fromLeaves ? leaf++ : merged++;
  };
  for (size_t made = n; made < 2 * n - 1; ++made) {
    const size_t a = take(made), b = take(made);
    weight[made] = weight[a] + weight[b];
    parent[a] = parent[b] = uint32_t(made);
  }
  std::vector<uint32_t> depth(2 * n - 1, 0);
  for (size_t node = 2 * n - 2; node-- > 0;) depth[node] = depth[parent[node]] + 1;

  // Clamped to maxBits, then the rarest codes shorter than maxBits lengthened one bit at a time
  // until Kraft's sum, in units of 2^-maxBits, is at most 1.
  std::vector<uint8_t> lengths(n);
  uint64_t kraft = 0;
  for (size_t i = 0; i < n; ++i) {
    lengths[byCount[i]] = uint8_t(std::min<uint32_t>(depth[i], maxBits));
    kraft += uint64_t(1) << (maxBits - lengths[byCount[i]]);
  }
  for (size_t i = 0; kraft > (uint64_t(1) << maxBits);) {
    while (lengths[byCount[i]] == maxBits) ++i;
    uint8_t& length = lengths[byCount[i]];
    kraft -= uint64_t(1) << (maxBits - length - 1);
    ++length;
  }
  return lengths;
}

bool isPrefixCode(const std::vector<uint8_t>& lengths, uint32_t maxBits) {
  uint64_t kraft = 0;
  for (const uint8_t length : lengths) {
    if (length == 0 || length > maxBits) return false;
    kraft += uint64_t(1) << (maxBits - length);
  }
  return kraft <= (uint64_t(1) << maxBits);
}

std::vector<uint32_t> canonicalCodes(const std::vector<uint8_t>& lengths) {
  std::vector<uint32_t> order(lengths.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return lengths[a] < lengths[b]; });
  std::vector<uint32_t> codes(lengths.size());
  uint32_t next = 0, length = 0;
  for (const uint32_t symbol : order) {
    next <<= lengths[symbol] - length;
    length = lengths[symbol];
    uint32_t reversed = 0;
    for (uint32_t bit = 0; bit < length; ++bit) reversed |= (next >> bit & 1) << (length - 1 - bit);
    codes[symbol] = reversed;
    ++next;
  }
  return codes;
}

std::vector<uint16_t> decodeTable(const std::vector<uint8_t>& lengths, uint32_t maxBits) {
  std::vector<uint16_t> table(size_t(1) << maxBits, kNoSymbol);
  const std::vector<uint32_t> codes = canonicalCodes(lengths);
  for (size_t symbol = 0; symbol < lengths.size(); ++symbol)
    for (size_t high = 0; high < (size_t(1) << (maxBits - lengths[symbol])); ++high)
      table[high << lengths[symbol] | codes[symbol]] = uint16_t(symbol);
  return table;
}

}  // namespace sb::delta_dag
