#include "schemes/interface/depth_decoder.h"

#include <algorithm>
#include <utility>

#include "schemes/interface/morton.h"

namespace sb {

std::vector<uint32_t> mortonOrder(std::span<const Query> queries, uint32_t resolution) {
  // Off the map, a query reads nothing: code 0 puts them first, out of the way.
  std::vector<std::pair<uint64_t, uint32_t>> keyed(queries.size());
  for (size_t q = 0; q < queries.size(); ++q) {
    const int64_t i = texelOf(queries[q].x, resolution), j = texelOf(queries[q].y, resolution);
    const uint64_t code =
        insideMap(i, j, resolution) ? mortonCode(uint32_t(i), uint32_t(j)) + 1 : 0;
    keyed[q] = {code, uint32_t(q)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<uint32_t> order(queries.size());
  for (size_t q = 0; q < keyed.size(); ++q) order[q] = keyed[q].second;
  return order;
}

}  // namespace sb
