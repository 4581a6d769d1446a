// SSE 4-wide value types for the packet kernels (Embree/tinybvh style: tiny inline
// wrappers around intrinsics, no virtuals, 16-byte aligned, SoA friendly).
#pragma once

#include <immintrin.h>

#include <cstdint>

namespace zz {

struct mask4;
struct int4;

// Four floats, one per ray lane.
struct alignas(16) float4 {
  __m128 v;

  float4() = default;
  float4(__m128 x) : v(x) {}
  explicit float4(float s) : v(_mm_set1_ps(s)) {}
  float4(float a, float b, float c, float d) : v(_mm_setr_ps(a, b, c, d)) {}
  operator __m128() const { return v; }

  static float4 load(const float* p) { return _mm_load_ps(p); }
  static float4 loadu(const float* p) { return _mm_loadu_ps(p); }
  void store(float* p) const { _mm_store_ps(p, v); }
  void storeu(float* p) const { _mm_storeu_ps(p, v); }

  float operator[](int i) const {
    alignas(16) float f[4];
    _mm_store_ps(f, v);
    return f[i];
  }
};

// A lane mask: all bits set in active lanes (the result of SSE comparisons).
struct alignas(16) mask4 {
  __m128 v;

  mask4() = default;
  mask4(__m128 x) : v(x) {}
  explicit mask4(bool b) : v(_mm_castsi128_ps(_mm_set1_epi32(b ? -1 : 0))) {}
  mask4(bool a, bool b, bool c, bool d)
      : v(_mm_castsi128_ps(_mm_setr_epi32(a ? -1 : 0, b ? -1 : 0, c ? -1 : 0, d ? -1 : 0))) {}
  operator __m128() const { return v; }

  // 4-bit mask, bit i = lane i (the index into the paper's 16-entry tables).
  int bits() const { return _mm_movemask_ps(v); }
  bool any() const { return bits() != 0; }
  bool all() const { return bits() == 0xF; }
  bool none() const { return bits() == 0; }
  bool operator[](int i) const { return (bits() >> i) & 1; }
  // The mask whose bits() are `b` (lane i active where bit i is set).
  static mask4 from_bits(int b) { return mask4(b & 1, b & 2, b & 4, b & 8); }
};

// Four 32-bit integers (primitive ids, lane indices).
struct alignas(16) int4 {
  __m128i v;

  int4() = default;
  int4(__m128i x) : v(x) {}
  explicit int4(int32_t s) : v(_mm_set1_epi32(s)) {}
  int4(int32_t a, int32_t b, int32_t c, int32_t d) : v(_mm_setr_epi32(a, b, c, d)) {}
  operator __m128i() const { return v; }

  void store(int32_t* p) const { _mm_store_si128(reinterpret_cast<__m128i*>(p), v); }
  int32_t operator[](int i) const {
    alignas(16) int32_t f[4];
    store(f);
    return f[i];
  }
};

// ---- float4 arithmetic -------------------------------------------------------
inline float4 operator+(float4 a, float4 b) { return _mm_add_ps(a, b); }
inline float4 operator-(float4 a, float4 b) { return _mm_sub_ps(a, b); }
inline float4 operator*(float4 a, float4 b) { return _mm_mul_ps(a, b); }
inline float4 operator/(float4 a, float4 b) { return _mm_div_ps(a, b); }
inline float4 operator-(float4 a) { return _mm_xor_ps(a, _mm_set1_ps(-0.0f)); }
inline float4& operator+=(float4& a, float4 b) { return a = a + b; }
inline float4& operator-=(float4& a, float4 b) { return a = a - b; }
inline float4& operator*=(float4& a, float4 b) { return a = a * b; }
inline float4 operator*(float4 a, float s) { return a * float4(s); }
inline float4 operator*(float s, float4 a) { return float4(s) * a; }
inline float4 operator+(float4 a, float s) { return a + float4(s); }
inline float4 operator-(float4 a, float s) { return a - float4(s); }

inline float4 min(float4 a, float4 b) { return _mm_min_ps(a, b); }
inline float4 max(float4 a, float4 b) { return _mm_max_ps(a, b); }
inline float4 abs(float4 a) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), a); }
inline float4 sqrt(float4 a) { return _mm_sqrt_ps(a); }
inline float4 rcp_exact(float4 a) { return _mm_div_ps(_mm_set1_ps(1.0f), a); }
inline float4 clamp(float4 a, float4 lo, float4 hi) { return min(max(a, lo), hi); }
inline float4 floor(float4 a) { return _mm_floor_ps(a); }
// The sign bit of a as a float (+0 or -0), for xor-ing signs (Woop et al. 2013).
inline float4 signmask(float4 a) { return _mm_and_ps(a, _mm_set1_ps(-0.0f)); }
inline float4 xorf(float4 a, float4 b) { return _mm_xor_ps(a, b); }

// ---- comparisons -> mask4 ----------------------------------------------------
inline mask4 operator<(float4 a, float4 b) { return _mm_cmplt_ps(a, b); }
inline mask4 operator<=(float4 a, float4 b) { return _mm_cmple_ps(a, b); }
inline mask4 operator>(float4 a, float4 b) { return _mm_cmpgt_ps(a, b); }
inline mask4 operator>=(float4 a, float4 b) { return _mm_cmpge_ps(a, b); }
inline mask4 operator==(float4 a, float4 b) { return _mm_cmpeq_ps(a, b); }
inline mask4 operator!=(float4 a, float4 b) { return _mm_cmpneq_ps(a, b); }
inline mask4 operator==(int4 a, int4 b) { return _mm_castsi128_ps(_mm_cmpeq_epi32(a, b)); }

inline mask4 operator&(mask4 a, mask4 b) { return _mm_and_ps(a, b); }
inline mask4 operator|(mask4 a, mask4 b) { return _mm_or_ps(a, b); }
inline mask4 operator^(mask4 a, mask4 b) { return _mm_xor_ps(a, b); }
inline mask4 operator!(mask4 a) { return _mm_xor_ps(a, _mm_castsi128_ps(_mm_set1_epi32(-1))); }
inline mask4 andnot(mask4 a, mask4 b) { return _mm_andnot_ps(a, b); }  // !a & b
inline mask4& operator&=(mask4& a, mask4 b) { return a = a & b; }
inline mask4& operator|=(mask4& a, mask4 b) { return a = a | b; }
inline mask4 isfinite(float4 a) { return abs(a) < float4(__builtin_inff()); }
inline mask4 isnan(float4 a) { return _mm_cmpunord_ps(a, a); }

// ---- selection ---------------------------------------------------------------
// m ? a : b, lane by lane.
inline float4 select(mask4 m, float4 a, float4 b) { return _mm_blendv_ps(b, a, m); }
inline int4 select(mask4 m, int4 a, int4 b) {
  return _mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(b), _mm_castsi128_ps(a), m));
}

// ---- horizontal --------------------------------------------------------------
inline float hsum(float4 a) {
  __m128 t = _mm_add_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(2, 3, 0, 1)));
  t = _mm_add_ps(t, _mm_shuffle_ps(t, t, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtss_f32(t);
}
inline float hmin(float4 a) {
  __m128 t = _mm_min_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(2, 3, 0, 1)));
  t = _mm_min_ps(t, _mm_shuffle_ps(t, t, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtss_f32(t);
}
inline float hmax(float4 a) {
  __m128 t = _mm_max_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(2, 3, 0, 1)));
  t = _mm_max_ps(t, _mm_shuffle_ps(t, t, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtss_f32(t);
}

// A 3-vector of packets (SoA): x, y, z each hold 4 lanes.
struct alignas(16) vec3x4 {
  float4 x, y, z;
};
inline vec3x4 operator+(const vec3x4& a, const vec3x4& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline vec3x4 operator-(const vec3x4& a, const vec3x4& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline vec3x4 operator*(const vec3x4& a, float4 s) { return {a.x * s, a.y * s, a.z * s}; }
inline vec3x4 operator*(const vec3x4& a, const vec3x4& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline float4 dot(const vec3x4& a, const vec3x4& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline vec3x4 cross(const vec3x4& a, const vec3x4& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline vec3x4 select(mask4 m, const vec3x4& a, const vec3x4& b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}

}  // namespace zz
