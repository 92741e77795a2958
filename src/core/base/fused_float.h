// Float helpers with a fixed rounding sequence, immune to the compiler's FMA contraction; any
// thread. GCC contracts a * b + c into an FMA by default and may do so differently at each inlined
// call site; intersection results must not depend on the call site (watertightness, and the BVH
// must return bit-identical hits to a brute-force loop), so every product and FMA here is explicit.
#pragma once
#include <cmath>

#include "core/base/types.h"

namespace frameless {

// a * b rounded to float, hidden from contraction into a following add.
inline float mul_exact(float a, float b) {
  float p = a * b;
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  asm("" : "+x"(p));
#elif defined(__GNUC__)
  asm("" : "+r"(p));
#endif
  return p;
}

// a * b + c with one rounding where the target has FMA, else two (no contraction without FMA).
inline float fmadd(float a, float b, float c) {
#if defined(__FMA__)
  return std::fma(a, b, c);
#else
  return mul_exact(a, b) + c;
#endif
}

inline float dot_exact(const Vec3& a, const Vec3& b) {
  return fmadd(a.x, b.x, fmadd(a.y, b.y, mul_exact(a.z, b.z)));
}

}  // namespace frameless
