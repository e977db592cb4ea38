// delta-dag's DAG of packs between hash-consing (delta_dag.cpp) and layout (pack_layout.h): packs
// turned by the square's symmetries, each stored in the orientation most of its references read,
// and the shared packs too small to be worth an address copied into their parents.
#pragma once

#include <cstdint>
#include <vector>

#include "schemes/delta-dag/pack_layout.h"

namespace sb::delta_dag {

// A reference to a pack, read under a symmetry.
struct PackReference {
  uint32_t pack;
  Symmetry symmetry;
};

// The first of the symmetries that read a pack the same as w, given the pack's self-symmetries
// (bit s: the pack reads the same under s as unturned): one reading per subtree, so that equal
// packs stay equal bit for bit.
Symmetry normalised(Symmetry w, uint8_t self);

// `pack` turned by u: child k becomes child apply(u, k), and its reference, read under w, is
// read under w after u⁻¹, so that the turned pack read under u reads as `pack` does.
// `selfSymmetries` holds those of the packs `pack` references.
Pack turned(const Pack& pack, Symmetry u, const std::vector<uint8_t>& selfSymmetries);
// The flags of `pack` turned by u.
inline uint8_t turnedFlags(uint8_t flags, Symmetry u) {
  uint32_t result = 0;
  for (uint32_t k = 0; k < kMhChildren; ++k)
    result |= childFlag(flags, int(k)) << (2 * kSymmetry.apply[u][k]);
  return uint8_t(result);
}

// Turns each pack to the orientation most of its references read it in (a private pack's one
// reference, the root's for the root), so that a reference carries a symmetry only where it reads
// a shared pack another way than most; the root's pack then reads unturned. A reading whose
// references' symmetries would take more bits than the pack's tree is split off: a pack of its
// own, turned its way, appended. `packs` must reference only packs of lower ids (as hash-consing
// finds them); split packs break that order. Returns the packs split off. `prediction`: packs'
// values are estimated as fittedValues fits them.
uint64_t orient(std::vector<Pack>& packs, std::vector<uint8_t>& selfSymmetries, PackReference root,
                bool prediction);

// The packs with each shared pack whose private tree takes fewer bits than the addresses it saves
// copied into every pack that references it, each copy turned the way it is read: a copy costs
// its tree once more and no address, as the first private child follows its parent. Returns the
// new root; the packs then reference only packs of lower ids. `copies` counts the packs added.
uint32_t copyCheapShared(std::vector<Pack>& packs, const std::vector<uint8_t>& selfSymmetries,
                         uint32_t rootPack, bool prediction, uint64_t& copies);

}  // namespace sb::delta_dag
