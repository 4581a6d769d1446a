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
}

TEST(Signature, EqualColoursDifferentSignaturesAreADiscontinuity) {
  const Rgb4 grey{float4(0.5f), float4(0.5f), float4(0.5f)};
  const float4 eps(0.05f);
  EXPECT_EQ(discontinuous4(grey, int4(1, 2, 3, 4), grey, int4(1, 2, 3, 4), eps), 0);
  EXPECT_EQ(discontinuous4(grey, int4(1, 2, 3, 4), grey, int4(1, 9, 3, 9), eps), 0b1010);
  // Corners TL, TR, BL, BR: the same colour, the right column in another light's shadow.
  EXPECT_EQ(corner_mask(grey, int4(7, 5, 7, 5), eps), 0b0011);  // d(A,B), d(C,D)
  EXPECT_EQ(corner_mask(grey, int4(7, 7, 7, 7), eps), 0);
  // Colour still counts on its own.
  const Rgb4 step{float4(0.5f, 0.6f, 0.5f, 0.6f), float4(0.5f), float4(0.5f)};
  EXPECT_EQ(corner_mask(step, int4(0), eps), 0b0011);
}

// One colour everywhere, two "objects" split by the vertical line x = pos.
struct SplitSignatureSource {
  float pos = 10.37f;
  Rgb4 sample4(float4, float4) const { return {float4(0.4f), float4(0.4f), float4(0.4f)}; }
  Rgb4 sample4(float4 px, float4 py, int4& sig) const {
    sig = select(px < float4(pos), int4(11), int4(12));
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
  for (int i = 0; i < 4; ++i) EXPECT_EQ(uint32_t(on[i]), star.object_id(x[i], y[i]));
}

TEST(Signature, TunerPatternsSignTheirSide) {
  PixelPattern p;  // inside where x >= 0.5
  const float4 px(0.2f, 0.7f, 0.49f, 0.51f), py(0.5f);
  int4 sig;
  PixelPatternSource{&p, true}.sample4(px, py, sig);
  EXPECT_EQ(sig[0], 1);
  EXPECT_EQ(sig[1], 2);
  EXPECT_EQ(sig[2], 1);
  EXPECT_EQ(sig[3], 2);
  PixelPatternSource{&p, false}.sample4(px, py, sig);
  EXPECT_EQ((sig == int4(0)).bits(), 0xF);
}

}  // namespace
}  // namespace zz
