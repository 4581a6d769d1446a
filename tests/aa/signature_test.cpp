// The signature predicate of levels 1 and 2 (aa/signature.h, ALGORITHM.md §11).
#include "aa/signature.h"

#include <gtest/gtest.h>

#include "aa/adaptive_pixel.h"
#include "aa/analytic.h"
#include "aa/table_tuning.h"
#include "core/error.h"
#include "test_sources.h"

namespace zz {
namespace {

TEST(Signature, ParsesNamesAndCommaLists) {
  EXPECT_EQ(parse_signature("none"), kSignatureNone);
  EXPECT_EQ(parse_signature("all"), kSignatureAll);
  EXPECT_EQ(parse_signature("lights"), kSignatureLights);
  EXPECT_EQ(parse_signature("object,secondary"), kSignatureObject | kSignatureSecondary);
  EXPECT_EQ(parse_signature("object,lights,secondary"), kSignatureAll);
  EXPECT_THROW(parse_signature("light"), Error);
  EXPECT_THROW(parse_signature("object,"), Error);
  EXPECT_THROW(parse_signature(""), Error);
  for (unsigned p = 0; p <= kSignatureAll; ++p) EXPECT_EQ(parse_signature(signature_name(p)), p);
  EXPECT_EQ(signature_name(kSignatureObject | kSignatureLights), "object,lights");
  // Bits beyond the three parts name nothing: the name is still canonical and parses back
  // to the parts (never "", which parse_signature refuses). Mutation testing: without the
  // mask, 8 named "" and 15 "object,lights,secondary", and no test changed.
  EXPECT_EQ(signature_name(8u), "none");
  EXPECT_EQ(signature_name(kSignatureAll | 8u), "all");
  EXPECT_EQ(signature_name(kSignatureLights | 16u), "lights");
  for (unsigned p = 0; p < 64; ++p) EXPECT_EQ(parse_signature(signature_name(p)), p & kSignatureAll) << p;
}

int4 whats(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  return int4(make_signature(a, 0, 0), make_signature(b, 0, 0), make_signature(c, 0, 0), make_signature(d, 0, 0));
}

TEST(Signature, LightsFoldIntoSlotsByIndexModuloTheSlotCount) {
  for (int l = 0; l < 32; ++l) EXPECT_EQ(fold_to_slots(1u << l), 1u << (l % kLightSlots)) << "light " << l;
  EXPECT_EQ(fold_to_slots(0u), 0u);
  EXPECT_EQ(fold_to_slots(~0u), kSlotMask);
  EXPECT_EQ(fold_to_slots((1u << 3) | (1u << 13) | (1u << 31)), (1u << 3) | (1u << 1));
}

TEST(Signature, EqualColoursDifferentSignaturesAreADiscontinuity) {
  const Rgb4 grey{float4(0.5f), float4(0.5f), float4(0.5f)};
  const float4 eps(0.05f);
  EXPECT_EQ(discontinuous4(grey, whats(1, 2, 3, 4), grey, whats(1, 2, 3, 4), eps), 0);
  EXPECT_EQ(discontinuous4(grey, whats(1, 2, 3, 4), grey, whats(1, 9, 3, 9), eps), 0b1010);
  // Corners TL, TR, BL, BR: the same colour, the right column on another object.
  EXPECT_EQ(corner_mask(grey, whats(7, 5, 7, 5), eps), 0b0011);  // d(A,B), d(C,D)
  EXPECT_EQ(corner_mask(grey, whats(7, 7, 7, 7), eps), 0);
  // Colour still counts on its own.
  const Rgb4 step{float4(0.5f, 0.6f, 0.5f, 0.6f), float4(0.5f), float4(0.5f)};
  EXPECT_EQ(corner_mask(step, int4(0), eps), 0b0011);
}

// A light's shadow bits differ only where that light could show at one of the two samples;
// `what` differs in any of its bits, and the layout keeps the three fields apart.
int4 all4(uint32_t what, uint32_t shows, uint32_t shadowed) {
  return int4(make_signature(what, shows, shadowed));
}

TEST(Signature, AShadowCountsWhereItsLightCouldShow) {
  const int light3 = 1 << 3, light12 = 1 << (12 % kLightSlots);
  const int4 lit = all4(5, light3, 0), shadowed_shows = all4(5, light3, light3), shadowed_faint = all4(5, 0, light3);
  EXPECT_EQ(signatures_differ4(lit, shadowed_shows), 0xF);
  EXPECT_EQ(signatures_differ4(lit, shadowed_faint), 0xF);  // shows at the lit one
  EXPECT_EQ(signatures_differ4(all4(5, 0, 0), shadowed_faint), 0);  // shows at neither
  // Both in its shadow: equal bits, whether or not it could show at either.
  EXPECT_EQ(signatures_differ4(shadowed_shows, shadowed_faint), 0);
  // Another light that shows does not make this one's flip count.
  EXPECT_EQ(signatures_differ4(all4(5, light12, 0), all4(5, light12, light3)), 0);
  // Lights 2 and 12 share a slot.
  EXPECT_EQ(signatures_differ4(all4(5, light12, 0), all4(5, light12, 1 << 2)), 0xF);
  // Every bit of `what` counts, the top one too.
  const uint32_t top = 1u << (kWhatBits - 1);
  EXPECT_EQ(signatures_differ4(all4(top, 0, 0), all4(0, 0, 0)), 0xF);
  EXPECT_EQ(signatures_differ4(all4(1, 0, 0), all4(0, 0, 0)), 0xF);
  EXPECT_EQ(signatures_differ4(int4(make_signature(1, 0, 0), 0, 0, make_signature(2, 0, 0)),
                               int4(make_signature(1, 0, 0), 0, make_signature(3, 0, 0), make_signature(2, 0, 0))),
            0b0100);
  static_assert(kWhatBits + 2 * kLightSlots == 32);
}

// One colour everywhere, two "objects" split by the vertical line x = pos.
struct SplitSignatureSource {
  float pos = 10.37f;
  Rgb4 sample4(float4, float4) const { return {float4(0.4f), float4(0.4f), float4(0.4f)}; }
  Rgb4 sample4(float4 px, float4 py, int4& sig) const {
    sig = select(px < float4(pos), int4(make_signature(11, 0, 0)), int4(make_signature(12, 0, 0)));
    return sample4(px, py);
  }
};
static_assert(SignedSampleSource<SplitSignatureSource>);

TEST(Signature, AnInvisibleSplitIsRefinedOnlyWithSignatures) {
  AdaptiveSettings s;
  s.tables = find_table_set("tuned");
  AaStats with, without;
  test::render(SplitSignatureSource{}, 24, 16, s, 64, 1, {}, &with);
  test::render(test::ConstantSource{0.4f, 0.4f, 0.4f}, 24, 16, s, 64, 1, {}, &without);  // no signatures
  EXPECT_EQ(without.level2_pixels, 0u);
  EXPECT_EQ(with.level2_pixels, 16u);  // the column of pixels the line crosses, one per row
  EXPECT_EQ(with.level3_pixels, 16u);  // and the tables trace its zone
  EXPECT_GT(with.rays_per_pixel(), without.rays_per_pixel());
}

TEST(Signature, SourcesWithoutSignaturesGiveZero) {
  test::ConstantSource c;
  int4 sig(5);
  sample4_signed(c, float4(0.0f), float4(0.0f), sig);
  EXPECT_EQ((sig == int4(0)).bits(), 0xF);
}

TEST(Signature, AnalyticObjectIdsFollowTheSetting) {
  const AnalyticImage star = make_analytic_image("star", 64);
  const float4 px(10.5f, 50.5f, 33.0f, 31.0f), py(32.0f, 32.0f, 10.0f, 54.0f);
  int4 off, on;
  AnalyticSource{&star}.sample4(px, py, off);
  AnalyticSource{&star, kSignatureObject}.sample4(px, py, on);
  EXPECT_EQ((off == int4(0)).bits(), 0xF);
  alignas(16) float x[4], y[4];
  px.store(x), py.store(y);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(on[i], make_signature(star.object_id(x[i], y[i]), 0, 0));
}

TEST(Signature, TunerPatternsSignTheirSide) {
  PixelPattern p;  // inside where x >= 0.5
  const float4 px(0.2f, 0.7f, 0.49f, 0.51f), py(0.5f);
  int4 sig;
  PixelPatternSource{&p, true}.sample4(px, py, sig);
  EXPECT_EQ(sig[0], make_signature(1, 0, 0));
  EXPECT_EQ(sig[1], make_signature(2, 0, 0));
  EXPECT_EQ(sig[2], make_signature(1, 0, 0));
  EXPECT_EQ(sig[3], make_signature(2, 0, 0));
  PixelPatternSource{&p, false}.sample4(px, py, sig);
  EXPECT_EQ((sig == int4(0)).bits(), 0xF);
}

}  // namespace
}  // namespace zz
