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
//
// A shadow bit counts only where the light could show: two samples differ in a light when
// one has its shadow ray blocked and the other not, and at one of them the light's
// unshadowed contribution would move the displayed colour by at least one 8-bit step.
// Where neither can show it (a faint rim light at grazing incidence, a terminator's
// flicker), the step is invisible in the image and refining it spends rays for nothing
// (car at 1024²: 0.06 rays/px). Hence the layout below; equality of whole words would
// count every flip.
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
  kSignatureLights = 2,     // lights whose shadow rays were blocked or attenuated, where they could show
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

// A signature's 32 bits: `what` (kWhatBits: the object and secondary hits, hashed, or an
// analytic region's id) above, per light slot (light l in slot l % kLightSlots) whether
// its light could show here, then whether its shadow ray was blocked or attenuated.
inline constexpr int kLightSlots = 10;
inline constexpr int kWhatBits = 32 - 2 * kLightSlots;
inline constexpr uint32_t kSlotMask = (1u << kLightSlots) - 1u;
// Per-light bits (bit l for light l % 32) folded into slots: bit l goes to slot l % kLightSlots.
constexpr uint32_t fold_to_slots(uint32_t per_light) {
  uint32_t slots = 0;
  for (int shift = 0; shift < 32; shift += kLightSlots) slots |= per_light >> shift;
  return slots & kSlotMask;
}
inline int32_t make_signature(uint32_t what, uint32_t shows, uint32_t shadowed) {
  return int32_t((what << (2 * kLightSlots)) | ((shows & kSlotMask) << kLightSlots) | (shadowed & kSlotMask));
}

// Bit i set where signatures p_i and q_i differ: in what they saw, or in a light's shadow
// bit where that light could show at either of them.
inline int signatures_differ4(int4 p, int4 q) {
  const __m128i x = _mm_xor_si128(p, q);
  const __m128i shows = _mm_srli_epi32(_mm_or_si128(p, q), kLightSlots);
  const __m128i what = _mm_and_si128(x, _mm_set1_epi32(int32_t(~0u << (2 * kLightSlots))));
  const __m128i shadow = _mm_and_si128(_mm_and_si128(x, shows), _mm_set1_epi32(int32_t(kSlotMask)));
  return (~(int4(_mm_or_si128(what, shadow)) == int4(0)).bits()) & 0xF;
}

// Lane permutation of 4 signatures, as shuffle4 does for colours (adaptive_pixel.h).
template <int a, int b, int c, int d>
inline int4 shuffle4(int4 v) {
  return _mm_shuffle_epi32(v, _MM_SHUFFLE(d, c, b, a));
}

// Folds one part of a signature into a 32-bit hash (a murmur3-style mix). Its top kWhatBits
// become `what`: distinct hits collide with probability about 2^-12, which would only miss
// a refinement where the colours agree too.
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
