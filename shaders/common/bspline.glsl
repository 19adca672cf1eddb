// 1-D B-spline weights N(d) and slopes dN/dd, d the particle's offset from a node in cells.
// Written in the subset GLSL shares with C++/GLM: the unit tests include this very file, so the weights the
// GPU uses are the ones the tests check (partition of unity, slopes against finite differences).
//
// The values are FIRN_PRECISE (GLSL's precise): computed as written, no multiply and add fused, so that two
// programs that transfer the same particle get the same bits (P2G by tiles and by blocks must add the same
// contributions: an NVIDIA driver fused them differently in two programs, docs/platform.md). C++ has no such
// qualifier; the host's copies (tests, references) are built for x86-64 without -march, where the compiler has no
// fused multiply-add to contract to.
#ifndef FIRN_PRECISE
#ifdef __cplusplus
#define FIRN_PRECISE
#else
#define FIRN_PRECISE precise
#endif
#endif

// Quadratic B-spline, support |d| < 1.5 (Blažević 2022 eq. 3.10; Jiang et al. 2016 eq. 123).
float quadraticBSpline(float d) {
  float a = abs(d);
  FIRN_PRECISE float n = 0.0;
  if (a < 0.5) {
    n = 0.75 - a * a;
  } else if (a < 1.5) {
    n = 0.5 * (1.5 - a) * (1.5 - a);
  }
  return n;
}

float quadraticBSplineSlope(float d) {
  float a = abs(d);
  FIRN_PRECISE float slope = 0.0;
  if (a < 0.5) {
    slope = -2.0 * d;
  } else if (a < 1.5) {
    slope = -sign(d) * (1.5 - a);
  }
  return slope;
}

// Cubic B-spline, support |d| < 2 (Stomakhin et al. 2013 eq. 4; Snow thesis 2015 eq. 18).
float cubicBSpline(float d) {
  float a = abs(d);
  FIRN_PRECISE float n = 0.0;
  if (a < 1.0) {
    n = 0.5 * a * a * a - a * a + 2.0 / 3.0;
  } else if (a < 2.0) {
    n = (2.0 - a) * (2.0 - a) * (2.0 - a) / 6.0;
  }
  return n;
}

float cubicBSplineSlope(float d) {
  float a = abs(d);
  FIRN_PRECISE float slope = 0.0;
  if (a < 1.0) {
    slope = sign(d) * (1.5 * a * a - 2.0 * a);
  } else if (a < 2.0) {
    slope = -sign(d) * 0.5 * (2.0 - a) * (2.0 - a);
  }
  return slope;
}
