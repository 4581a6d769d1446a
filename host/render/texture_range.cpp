#include "render/texture_range.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

#include "scene/scene.h"

namespace zz {

namespace {

constexpr int kFirstBlock = 2;  // levels start at 4 x 4 blocks; finer boxes read the texels

struct Span {
  long first = 0, last = -1;  // inclusive, within [0, n)
};

// The texels [a, b] (a <= b, unwrapped) as at most two spans within [0, n).
int wrapped_spans(long a, long b, int n, TextureWrap wrap, Span out[2]) {
  if (b - a + 1 >= n) {
    out[0] = {0, n - 1};
    return 1;
  }
  if (a >= 0 && b < n) {
    out[0] = {a, b};
    return 1;
  }
  const long wa = wrap_index(a, n, wrap), wb = wrap_index(b, n, wrap);
  switch (wrap) {
    case TextureWrap::Repeat:
      if (wa <= wb) {
        out[0] = {wa, wb};
        return 1;
      }
      out[0] = {wa, n - 1};
      out[1] = {0, wb};
      return 2;
    case TextureWrap::MirroredRepeat: {
      // Shorter than a period, the span crosses at most one mirror line, where the texel
      // on either side is the same border texel: the wrapped texels are one span through it.
      long lo = std::min(wa, wb), hi = std::max(wa, wb);
      const long line = long(std::floor(double(b) / n)) * n;  // the last multiple of n <= b
      if (line > a) {
        const long border = wrap_index(line, n, wrap);
        lo = std::min(lo, border);
        hi = std::max(hi, border);
      }
      out[0] = {lo, hi};
      return 1;
    }
    case TextureWrap::ClampToEdge: out[0] = {wa, wb}; return 1;
  }
  out[0] = {0, n - 1};
  return 1;
}

// The unwrapped texels filtering reads between coordinates lo and hi along an axis of n texels.
void texels_between(float lo, float hi, int n, TextureWrap wrap, TextureFilter filter, long& a, long& b) {
  // One period's shift keeps the conversion to long in range (1e20 repeats); clamping
  // leaves the box beyond [-1, 2] on the border texels anyway.
  float shift = 0.0f;
  if (wrap == TextureWrap::Repeat) shift = std::floor(lo);
  if (wrap == TextureWrap::MirroredRepeat) shift = 2.0f * std::floor(0.5f * lo);
  lo -= shift, hi -= shift;
  if (wrap == TextureWrap::ClampToEdge) lo = std::clamp(lo, -1.0f, 2.0f), hi = std::clamp(hi, -1.0f, 2.0f);
  hi = std::min(hi, lo + 4.0f);  // a box over whole periods reads every texel anyway
  const double w = double(n);
  if (filter == TextureFilter::Nearest) {
    a = long(std::floor(double(lo) * w)), b = long(std::floor(double(hi) * w));
  } else {
    a = long(std::floor(double(lo) * w - 0.5)), b = long(std::floor(double(hi) * w - 0.5)) + 1;
  }
}

void include(TextureMoments& m, const TextureMoments& block) {
  m.sum += block.sum;
  m.sum_sq += block.sum_sq;
  m.count += block.count;
}
void include(TextureMoments& m, glm::vec3 texel) { include(m, TextureMoments{texel, texel * texel, 1.0f}); }

}  // namespace

TextureSpread::TextureSpread(const Texture& base) {
  const int w = base.width, h = base.height;
  if (w <= 0 || h <= 0 || base.texel_count() < size_t(w) * size_t(h)) return;
  // The 4 x 4 blocks from the texels, then each level from 2 x 2 blocks of the last.
  Level first;
  first.width = std::max(1, w >> kFirstBlock);
  first.height = std::max(1, h >> kFirstBlock);
  first.blocks.assign(size_t(first.width) * size_t(first.height), TextureMoments{});
  // Rows of blocks in parallel (a 2048² map: 29 ms serially), each summed in texel order,
  // so the sums do not depend on the thread count.
  tbb::parallel_for(0, first.height, [&](int by) {
    const int y_end = by == first.height - 1 ? h : (by + 1) << kFirstBlock;
    for (int y = by << kFirstBlock; y < y_end; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(by) * size_t(first.width) + size_t(std::min(x >> kFirstBlock, first.width - 1));
        include(first.blocks[i], glm::vec3(base.texel(size_t(y) * size_t(w) + size_t(x))));
      }
  });
  levels_.push_back(std::move(first));
  while (levels_.back().width > 1 || levels_.back().height > 1) {
    const Level& fine = levels_.back();
    Level coarse;
    coarse.width = std::max(1, fine.width / 2);
    coarse.height = std::max(1, fine.height / 2);
    coarse.blocks.assign(size_t(coarse.width) * size_t(coarse.height), TextureMoments{});
    for (int y = 0; y < fine.height; ++y)
      for (int x = 0; x < fine.width; ++x) {
        const size_t i = size_t(std::min(y / 2, coarse.height - 1)) * size_t(coarse.width) +
                         size_t(std::min(x / 2, coarse.width - 1));
        include(coarse.blocks[i], fine.blocks[size_t(y) * size_t(fine.width) + size_t(x)]);
      }
    levels_.push_back(std::move(coarse));
  }
}

TextureMoments TextureSpread::over(const Texture& base, glm::vec2 lo, glm::vec2 hi) const {
  const TextureMoments all = levels_.back().blocks[0];
  if (!(std::isfinite(lo.x) && std::isfinite(lo.y) && std::isfinite(hi.x) && std::isfinite(hi.y))) return all;
  long ax, bx, ay, by;
  texels_between(lo.x, hi.x, base.width, base.wrap_s, base.filter, ax, bx);
  texels_between(lo.y, hi.y, base.height, base.wrap_t, base.filter, ay, by);
  Span xs[2], ys[2];
  const int nx = wrapped_spans(ax, bx, base.width, base.wrap_s, xs);
  const int ny = wrapped_spans(ay, by, base.height, base.wrap_t, ys);

  TextureMoments r;
  long widest = 0;
  for (int i = 0; i < nx; ++i) widest = std::max(widest, xs[i].last - xs[i].first + 1);
  for (int j = 0; j < ny; ++j) widest = std::max(widest, ys[j].last - ys[j].first + 1);
  if (widest <= (1L << kFirstBlock) + 1) {  // at most 5 x 5 texels per span: read them
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (long y = ys[j].first; y <= ys[j].last; ++y)
          for (long x = xs[i].first; x <= xs[i].last; ++x) {
            include(r, glm::vec3(base.texel(size_t(y) * size_t(base.width) + size_t(x))));
          }
    return r;
  }
  // The finest level on which every span covers at most three blocks.
  size_t l = 0;
  int shift = kFirstBlock;
  auto blocks = [&](const Span& s) { return (s.last >> shift) - (s.first >> shift) + 1; };
  for (;; ++l, ++shift) {
    if (l + 1 == levels_.size()) break;
    long most = 0;
    for (int i = 0; i < nx; ++i) most = std::max(most, blocks(xs[i]));
    for (int j = 0; j < ny; ++j) most = std::max(most, blocks(ys[j]));
    if (most <= 3) break;
  }
  const Level& level = levels_[l];
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      for (long y = ys[j].first >> shift; y <= (ys[j].last >> shift); ++y)
        for (long x = xs[i].first >> shift; x <= (xs[i].last >> shift); ++x) {
          const size_t k = size_t(std::min<long>(y, level.height - 1)) * size_t(level.width) +
                           size_t(std::min<long>(x, level.width - 1));
          include(r, level.blocks[k]);
        }
  return r;
}

uint64_t TextureSpread::bytes(int width, int height) {
  if (width <= 0 || height <= 0) return 0;
  uint64_t total = 0;
  int w = std::max(1, width >> kFirstBlock), h = std::max(1, height >> kFirstBlock);
  for (;;) {
    total += uint64_t(w) * uint64_t(h) * sizeof(TextureMoments);
    if (w == 1 && h == 1) return total;
    w = std::max(1, w / 2), h = std::max(1, h / 2);
  }
}

namespace {

// Whether each scene texture is some material's normal map.
std::vector<bool> normal_maps(const Scene& scene) {
  std::vector<bool> used(scene.textures.size(), false);
  for (const Material& m : scene.materials)
    if (m.normal_texture.used() && size_t(m.normal_texture.index) < used.size()) used[size_t(m.normal_texture.index)] = true;
  return used;
}

}  // namespace

uint64_t normal_map_spread_bytes(const Scene& scene) {
  const std::vector<bool> used = normal_maps(scene);
  uint64_t total = 0;
  for (size_t i = 0; i < used.size(); ++i)
    if (used[i]) total += TextureSpread::bytes(scene.textures[i].width, scene.textures[i].height);
  return total;
}

glm::vec3 TextureMoments::deviation() const {
  if (!(count > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 mean = sum / count;
  return glm::sqrt(glm::max(sum_sq / count - mean * mean, glm::vec3(0.0f)));
}

std::vector<TextureSpread> normal_map_spreads(const Scene& scene) {
  const std::vector<bool> used = normal_maps(scene);
  std::vector<TextureSpread> spreads(used.size());
  for (size_t i = 0; i < used.size(); ++i)
    if (used[i]) spreads[i] = TextureSpread(scene.textures[i]);
  return spreads;
}

float normal_map_spread(const Scene& scene, const std::vector<TextureSpread>& spreads, const SurfaceProbe c[4]) {
  const uint32_t m = c[0].material;
  if (m >= scene.materials.size()) return 0.0f;
  for (int k = 1; k < 4; ++k)
    if (c[k].material != m) return 0.0f;
  const Material& material = scene.materials[m];
  const TextureRef& ref = material.normal_texture;
  const size_t index = size_t(ref.index);
  if (!ref.used() || index >= spreads.size() || spreads[index].empty()) return 0.0f;
  glm::vec2 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (int k = 0; k < 4; ++k) {
    const glm::vec2 st = ref.at(c[k].uv0, c[k].uv1);
    lo = glm::min(lo, st);
    hi = glm::max(hi, st);
  }
  const glm::vec3 deviation = spreads[index].over(scene.textures[index], lo, hi).deviation();
  // Texel rgb maps to the tangent-space normal (2 rgb - 1) with x and y scaled
  // (render/normal_map.h): the normals' RMS distance from their mean, times kSpreadDeviations.
  const glm::vec3 scale(std::fabs(material.normal_scale), std::fabs(material.normal_scale), 1.0f);
  return kSpreadDeviations * glm::length(2.0f * deviation * scale);
}

}  // namespace zz
