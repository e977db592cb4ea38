#include "fuzz/exercise_decoder.h"

#include <cstdio>
#include <cstdlib>
#include <vector>

namespace sb::fuzz {

void exerciseDecoder(const Decoder& decoder) {
  std::vector<Query> queries;
  constexpr int kGrid = 8;
  const float edges[] = {-0.01f, 0.0f, 0.999999f, 1.0f};
  for (float z : {0.0f, 0.25f, 0.5f, 0.999f, 1.0f}) {
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i)
        queries.push_back({(i + 0.5f) / kGrid, (j + 0.5f) / kGrid, z});
    for (float x : edges)
      for (float y : edges) queries.push_back({x, y, z});
  }
  std::vector<float> answers(queries.size());
  for (int k : {1, 3, 17}) {
    decoder.lookup(queries, k, answers);
    for (size_t q = 0; q < queries.size(); ++q)
      if (!(answers[q] >= 0.0f && answers[q] <= 1.0f)) {
        std::fprintf(stderr, "visibility %g at (%g, %g, %g), k = %d is not in [0, 1]\n", answers[q],
                     queries[q].x, queries[q].y, queries[q].z, k);
        std::abort();
      }
  }
  (void)totalBytes(decoder.size());
}

}  // namespace sb::fuzz
