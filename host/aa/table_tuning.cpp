#include "aa/table_tuning.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <random>

#include "aa/adaptive_pixel.h"

namespace zz {

bool PixelPattern::inside_at(float x, float y) const {
  const float d = nx * x + ny * y - c;
  switch (kind) {
    case Edge: return d >= 0.0f;
    case ThinLine: return std::fabs(d) < 0.5f * width;
    case Wedge: return d >= 0.0f && nx2 * x + ny2 * y - c2 >= 0.0f;
  }
  return false;
}

float PixelPattern::eval(float x, float y) const { return inside_at(x, y) ? inside : outside; }

Rgb4 PixelPatternSource::sample4(float4 px, float4 py) const {
  alignas(16) float x[4], y[4], g[4];
  px.store(x);
  py.store(y);
  for (int i = 0; i < 4; ++i) g[i] = pattern->eval(x[i], y[i]);
  const float4 v = float4::load(g);
  return {v, v, v};
}

Rgb4 PixelPatternSource::sample4(float4 px, float4 py, int4& sig) const {
  alignas(16) float x[4], y[4];
  alignas(16) int32_t side[4] = {0, 0, 0, 0};
  if (signatures) {
    px.store(x);
    py.store(y);
    for (int i = 0; i < 4; ++i) side[i] = pattern->inside_at(x[i], y[i]) ? 2 : 1;
  }
  sig = int4(make_signature(uint32_t(side[0]), 0, 0), make_signature(uint32_t(side[1]), 0, 0),
             make_signature(uint32_t(side[2]), 0, 0), make_signature(uint32_t(side[3]), 0, 0));
  return sample4(px, py);
}

namespace {

// Offsets of a line with unit normal n that crosses the unit pixel: c in (min, max) of
// n.p over the corners.
void crossing_range(float nx, float ny, float& lo, float& hi) {
  const float v[4] = {0.0f, nx, ny, nx + ny};
  lo = *std::min_element(v, v + 4);
  hi = *std::max_element(v, v + 4);
}

}  // namespace

Population make_population(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const float two_pi = 2.0f * std::numbers::pi_v<float>;
  // Contrast pairs (inside, outside): strong and medium, both polarities via the angle.
  const float levels[][2] = {{1.0f, 0.0f}, {0.8f, 0.1f}, {0.5f, 0.05f}, {1.0f, 0.3f}};
  std::vector<PixelPattern> all;
  all.reserve(size_t(n));
  for (int i = 0; i < n; ++i) {
    PixelPattern p;
    const float a = two_pi * u01(rng);
    p.nx = std::cos(a), p.ny = std::sin(a);
    float lo, hi;
    crossing_range(p.nx, p.ny, lo, hi);
    const int lv = int(u01(rng) * 4.0f) & 3;
    p.inside = levels[lv][0], p.outside = levels[lv][1];
    const float kind = u01(rng);
    if (kind < 0.55f) {  // straight edge anywhere across the pixel
      p.kind = PixelPattern::Edge;
      p.c = lo + (hi - lo) * u01(rng);
    } else if (kind < 0.7f) {  // corner cut: within 35 % of the range from a corner
      p.kind = PixelPattern::Edge;
      const float t = 0.35f * u01(rng);
      p.c = (u01(rng) < 0.5f) ? lo + (hi - lo) * t : hi - (hi - lo) * t;
    } else if (kind < 0.85f) {  // thin line 0.1 .. 0.5 px wide
      p.kind = PixelPattern::ThinLine;
      p.width = 0.1f + 0.4f * u01(rng);
      p.c = lo + (hi - lo) * u01(rng);
    } else {  // two edges meeting at an apex inside the pixel
      p.kind = PixelPattern::Wedge;
      const float ax = u01(rng), ay = u01(rng);
      const float opening = (0.25f + 0.6f * u01(rng)) * std::numbers::pi_v<float>;
      const float b = a + std::numbers::pi_v<float> - opening;
      p.nx2 = std::cos(b), p.ny2 = std::sin(b);
      p.c = p.nx * ax + p.ny * ay;
      p.c2 = p.nx2 * ax + p.ny2 * ay;
    }
    all.push_back(p);
  }
  Population pop;
  for (size_t i = 0; i < all.size(); ++i) (i % 4 == 3 ? pop.held_out : pop.train).push_back(all[i]);
  return pop;
}

PatternRecord evaluate_pattern(const PixelPattern& p, const AdaptiveSettings& settings) {
  PixelPatternSource source{&p, (settings.signature & kSignatureObject) != 0};
  const float4 eps(settings.eps);
  // Level 1: the pixel's 4 corners as one packet (TL, TR, BL, BR).
  int4 sig;
  const Rgb4 lin = source.sample4(float4(0, 1, 0, 1), float4(0, 0, 1, 1), sig);
  const Rgb4 disp = settings.tonemap.apply4(lin);
  float4 tl, tr, bl, br;
  aos_from_soa(lin, tl, tr, bl, br);
  // The sampler's own rule (adaptive_pixel.h); the tuner's pixels have no visibility map.
  const Level1 l1 = decide_level1(disp, sig, eps, /*geo=*/false, settings.refine_all);

  PatternRecord r;
  alignas(16) float4 lattice[kLatticePoints];
  const Orientation o = l1.orientation;
  const float4 zero(0.0f);
  const Level2 l2 = trace_level2(source, zero, zero, o, lin, disp, sig, settings.tonemap, eps);
  trace_level3(source, zero, zero, l2, kAllZones, lattice);
  const float reference = box_lattice(tl, tr, bl, br, lattice)[0];
  if (!l1.refine) {
    r.error.fill(std::fabs(corner_mean(tl, tr, bl, br)[0] - reference));
    return r;
  }
  r.refined = true;
  r.b = uint8_t(l2.b), r.c0 = uint8_t(l2.c0), r.c1 = uint8_t(l2.c1);
  r.hdr = settings.hdr_zones ? uint8_t(hdr_zones(l2, settings.tonemap.exposure)) : 0;
  r.split = settings.split_unflagged ? uint8_t(split_zones(l2)) : 0;
  for (int z = 0; z < 32; ++z) {
    trace_level3(source, zero, zero, l2, z, lattice);
    r.error[z] = std::fabs(box_lattice(tl, tr, bl, br, lattice)[0] - reference);
  }
  return r;
}

std::vector<PatternRecord> evaluate_population(const std::vector<PixelPattern>& patterns,
                                               const AdaptiveSettings& settings) {
  std::vector<PatternRecord> out;
  out.reserve(patterns.size());
  for (const PixelPattern& p : patterns) out.push_back(evaluate_pattern(p, settings));
  return out;
}

namespace {

double rays_of(const PatternRecord& r, int zones) { return r.refined ? refined_rays(zones) : 1.0; }

}  // namespace

TableScore score_tables(const TableSet& t, const std::vector<PatternRecord>& records) {
  TableScore s;
  for (const PatternRecord& r : records) {
    const int z = r.refined ? decide_zones(t, r.b, r.c0, r.c1, r.hdr, r.split, /*geo=*/false, GeoPolicy::Paper, false, 0, r.split != 0) : 0;
    s.error += r.error[z];
    s.rays += rays_of(r, z);
  }
  if (!records.empty()) s.error /= double(records.size()), s.rays /= double(records.size());
  return s;
}

TableSet tune_tables(const TableSet& start, const std::vector<PatternRecord>& records, double lambda) {
  // Entries 0..15 = b, 16..31 = c0, 32..47 = c1.
  std::array<uint8_t, 48> t{};
  for (int i = 0; i < 16; ++i) t[i] = start.b[i], t[16 + i] = start.c0[i], t[32 + i] = start.c1[i];
  std::array<std::vector<uint32_t>, 48> users;
  for (uint32_t i = 0; i < records.size(); ++i)
    if (records[i].refined) {
      users[records[i].b].push_back(i);
      users[16 + records[i].c0].push_back(i);
      users[32 + records[i].c1].push_back(i);
    }
  // The zones of a record: decide_zones without a geo flag, i.e. the three entries, hdr and split OR-ed.
  auto cost_of = [&](int entry) {
    double c = 0;
    for (uint32_t i : users[entry]) {
      const PatternRecord& r = records[i];
      const int z = t[r.b] | t[16 + r.c0] | t[32 + r.c1] | r.hdr | r.split;
      c += r.error[z] + lambda * rays_of(r, z);
    }
    return c;
  };
  for (int sweep = 0; sweep < 50; ++sweep) {
    bool improved = false;
    for (int e = 0; e < 48; ++e) {
      if (users[e].empty()) continue;
      const uint8_t keep = t[e];
      double best = cost_of(e);
      uint8_t best_v = keep;
      for (int v = 0; v < 32; ++v) {
        if (v == keep) continue;
        t[e] = uint8_t(v);
        const double c = cost_of(e);
        if (c < best - 1e-12 * std::max(1.0, std::fabs(best))) best = c, best_v = uint8_t(v);
      }
      t[e] = best_v;
      improved |= best_v != keep;
    }
    if (!improved) break;
  }
  TableSet out{};
  for (int i = 0; i < 16; ++i) out.b[i] = t[i], out.c0[i] = t[16 + i], out.c1[i] = t[32 + i];
  return out;
}

}  // namespace zz
