// 1-D B-spline weights N(d) and slopes dN/dd, d the particle's offset from a node in cells.
// Written in the subset GLSL shares with C++/GLM: the unit tests include this very file, so the weights the
// GPU uses are the ones the tests check (partition of unity, slopes against finite differences).

// Quadratic B-spline, support |d| < 1.5 (Blažević 2022 eq. 3.10; Jiang et al. 2016 eq. 123).
float quadraticBSpline(float d) {
  float a = abs(d);
  if (a < 0.5) return 0.75 - a * a;
  if (a < 1.5) return 0.5 * (1.5 - a) * (1.5 - a);
  return 0.0;
}

float quadraticBSplineSlope(float d) {
  float a = abs(d);
  if (a < 0.5) return -2.0 * d;
  if (a < 1.5) return -sign(d) * (1.5 - a);
  return 0.0;
}

// Cubic B-spline, support |d| < 2 (Stomakhin et al. 2013 eq. 4; Snow thesis 2015 eq. 18).
float cubicBSpline(float d) {
  float a = abs(d);
  if (a < 1.0) return 0.5 * a * a * a - a * a + 2.0 / 3.0;
  if (a < 2.0) return (2.0 - a) * (2.0 - a) * (2.0 - a) / 6.0;
  return 0.0;
}

float cubicBSplineSlope(float d) {
  float a = abs(d);
  if (a < 1.0) return sign(d) * (1.5 * a * a - 2.0 * a);
  if (a < 2.0) return -sign(d) * 0.5 * (2.0 - a) * (2.0 - a);
  return 0.0;
}
