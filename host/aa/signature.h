// Sample signatures (ALGORITHM.md §11, our extension of the paper): with its colour a
// sample may carry a 32-bit integer saying *what* it saw — the object (material) of the
// primary hit, which lights' shadow rays were blocked, what the first reflection and
// refraction rays hit. Levels 1 and 2 then call two samples discontinuous when their
// display colours differ by more than eps *or* their signatures differ, so a shadow step
// below eps from one of many lights, a material boundary of equal brightness or an edge
// seen only in a mirror still sends the pixel to the zone tables. One SSE compare per 4
// pairs, OR-ed into the same 4-bit masks: the tables do not change.
//
// A source that has no signatures (or whose parts are all switched off) returns 0 for
// every sample, so the predicate is exactly the paper's. Like the colour, a signature
// depends only on its own lane's point (the determinism contract of sample_source.h).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "aa/sample_source.h"
#include "core/simd.h"

namespace zz {

// Parts of a signature, switchable one by one (--signature).
enum SignatureParts : unsigned {
  kSignatureNone = 0,
  kSignatureObject = 1,     // material of the primary hit (0 = background)
  kSignatureLights = 2,     // bitmask of lights whose shadow rays were blocked or attenuated
  kSignatureSecondary = 4,  // materials hit by the first reflection and refraction rays
  kSignatureAll = 7,
};

// "none", "all", or a comma list of object, lights, secondary. Throws zz::Error.
unsigned parse_signature(std::string_view text);
// The canonical name: none, all, or the comma list in the order above.
std::string signature_name(unsigned parts);

// A source that also returns signatures: sample4(px, py, sig) fills sig's lanes.
template <class S>
concept SignedSampleSource = SampleSource<S> && requires(S& source, float4 px, float4 py, int4& sig) {
  { source.sample4(px, py, sig) } -> std::same_as<Rgb4>;
};

// Colour and signature of 4 points; signature 0 for sources without them.
template <SampleSource S>
inline Rgb4 sample4_signed(S& source, float4 px, float4 py, int4& sig) {
  if constexpr (SignedSampleSource<S>) {
    return source.sample4(px, py, sig);
  } else {
    sig = int4(0);
    return source.sample4(px, py);
  }
}

// Bit i set where signatures p_i and q_i differ.
inline int signatures_differ4(int4 p, int4 q) { return (~(p == q).bits()) & 0xF; }

// Lane permutation of 4 signatures, as shuffle4 does for colours (adaptive_pixel.h).
template <int a, int b, int c, int d>
inline int4 shuffle4(int4 v) {
  return _mm_shuffle_epi32(v, _MM_SHUFFLE(d, c, b, a));
}

// Folds one part of a signature into the 32-bit hash (a murmur3-style mix: distinct parts
// collide with probability about 2^-32, which would only miss a refinement).
inline uint32_t signature_mix(uint32_t hash, uint32_t part) {
  uint32_t k = part * 0xCC9E2D51u;
  k = (k << 15) | (k >> 17);
  hash ^= k * 0x1B873593u;
  hash = ((hash << 13) | (hash >> 19)) * 5u + 0xE6546B64u;
  hash ^= hash >> 16;
  hash *= 0x85EBCA6Bu;
  hash ^= hash >> 13;
  return hash;
}

}  // namespace zz
