// A length-limited canonical prefix code (Huffman 1952), for delta-dag's pack formats: a frequent
// format's code is short. Codes are read from the low bits of a little-endian bit stream, so each
// canonical code is stored bit-reversed (as DEFLATE's, RFC 1951 §3.2.2), and a table indexed by
// the stream's next `longest` bits decodes one in a single read.
#pragma once

#include <cstdint>
#include <vector>

namespace sb::delta_dag {

constexpr uint32_t kMaxCodeBits = 16;
constexpr uint16_t kNoSymbol = 0xffff;  // a decode table's entry that no code starts

// The lengths of a Huffman code for these counts (each ≥ 1; at most 2^maxBits of them), none
// longer than maxBits: where Huffman's are longer, the rarest symbols' codes are lengthened until
// the code fits (Kraft's sum at most 1), the longest first clamped to maxBits.
std::vector<uint8_t> huffmanLengths(const std::vector<uint64_t>& counts, uint32_t maxBits);

// Whether codes of these lengths (each 1 … maxBits) exist: Kraft's sum at most 1.
bool isPrefixCode(const std::vector<uint8_t>& lengths, uint32_t maxBits);

// The canonical code of these lengths (codes in order of length, then of symbol), bit-reversed.
std::vector<uint32_t> canonicalCodes(const std::vector<uint8_t>& lengths);

// Per value of the next maxBits bits, the symbol whose code they begin with, or kNoSymbol.
std::vector<uint16_t> decodeTable(const std::vector<uint8_t>& lengths, uint32_t maxBits);

}  // namespace sb::delta_dag
