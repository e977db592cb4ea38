// Lookups a structure may offer beside the exact ones of DESIGN §4, reached through
// Decoder::hierarchicalLookup() and Decoder::voxelOccupancy(): approximate filters for distant
// shadows, reported against exact PCF, not checked. And what a decoder with a cache reports
// of it, through Decoder::blockCacheStatistics().
#pragma once

#include <cstdint>
#include <span>

#include "schemes/interface/scheme.h"

namespace sb {

// Depth schemes whose structure holds every coarser level of the map (the MH family: each level
// of the hierarchy is a complete shadow map, Scandolo et al. 2016a) answer hierarchical PCF: the
// k×k filter over the map `coarser` levels up, whose texels cover 2^coarser × 2^coarser of the
// full map's.
class HierarchicalLookup {
 public:
  virtual ~HierarchicalLookup() = default;
  virtual int levels() const = 0;  // log2 R: coarser may be 0 … levels
  virtual void lookupCoarse(std::span<const Query> queries, int coarser, int k,
                            std::span<float> visibility) const = 0;
};

// Sintorn §5 VOAA: a CPVS node's header keeps the fraction of its voxels that are lit, so the
// node of side s around a query's voxel answers an area filter of about s² texels in one read.
class VoxelOccupancy {
 public:
  virtual ~VoxelOccupancy() = default;
  // The node depth whose cubes have `side` voxels. Throws std::invalid_argument for a side that
  // is not a power of two between the leaf parents' and R, or a depth that the top-level grid
  // replaces (it keeps no occupancy there).
  virtual uint32_t depthOfSide(uint32_t side) const = 0;
  virtual void litFraction(std::span<const Query> queries, uint32_t depth,
                           std::span<float> fraction) const = 0;
};

// Decoders that decompress blocks into a cache of each looking-up thread (sm-zstd) count that
// thread's lookups the cache answered and the blocks it decompressed, so that the harness can
// put a hit rate beside a single-thread timing (issue 13). Their cost per query depends on the
// batch, so the harness times them on whole frames.
class BlockCacheStatistics {
 public:
  struct Counts {
    uint64_t hits = 0, misses = 0;
  };
  virtual ~BlockCacheStatistics() = default;
  // The calling thread's counts since its cache last began serving this decoder.
  virtual Counts threadCounts() const = 0;
};

}  // namespace sb
