// The 3×3 SVD of shaders/common/svd3.glsl, run on the GPU and compared with a double-precision reference.
//
// Every family of matrices is decomposed by one dispatch of a test kernel; each result is checked against
// the contract of svd3(): A = U diag(sigma) Vᵀ, U and V proper rotations, sigma sorted with the sign of
// det A on the last value, and sigma equal to the singular values of A.
//
// Tolerances. The kernel works in float32, ε = 2^-23 ≈ 1.2e-7. Each of the 18 Jacobi rotations (6 sweeps),
// the product B = A V and the 3 QR rotations adds O(ε) relative error, and llvmpipe's inversesqrt is itself
// off by up to 1.5 ulp, so errors of ten or so ε relative to ‖A‖_F are expected (McAdams et al. 2011
// report maxima near 1e-6 ≈ 8ε). Measured maxima on llvmpipe (Mesa 22.3.6, LLVM 15), in units of ε, over
// the 300 matrices per family used here / over 10^5 per family from the same generators:
//   reconstruction ‖UΣVᵀ − A‖_F / ‖A‖_F     8.3 / 12  (61 for exact rank 2: see below)
//   ‖UᵀU − I‖_F, ‖VᵀV − I‖_F                 11.6 / 15.7
//   |det U − 1|, |det V − 1|                   9.8 / 11.9
//   ordering slack / ‖A‖_F                    1.9 / 2.8
//   |σ_i − σ_i,ref| / ‖A‖_F                   3.8 / 5.1
// The tolerances are about three times the first column, which also covers the second. The exception is
// inherent to forming AᵀA in float: when σ2 = 0 and σ1 is a small fraction of σ0, the singular vectors of
// that pair are rotated by up to about ε σ0² / σ1², and the reconstruction error reaches tens of ε.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "GlTest.h"
#include "gl/Buffer.h"
#include "gl/Program.h"
#include "gl/ShaderLibrary.h"

namespace {

using firn::gl::Buffer;
using firn::gl::Program;
using firn::gl::ShaderLibrary;
using firn::gl::ShaderOptions;

// Limits relative to ‖A‖_F unless stated; see the measured maxima at the top of the file.
constexpr double kFloatEpsilon = 0x1p-23;
constexpr double kReconstructionTolerance = 24 * kFloatEpsilon;  // ‖UΣVᵀ − A‖_F / ‖A‖_F
constexpr double kOrthogonalityTolerance = 32 * kFloatEpsilon;   // ‖UᵀU − I‖_F and |det − 1| for U, V
constexpr double kOrderingTolerance = 8 * kFloatEpsilon;         // bound on σ1 − σ0, |σ2| − σ1 and −σ1
constexpr double kSingularValueTolerance = 12 * kFloatEpsilon;   // |σ_i − σ_i,ref| / ‖A‖_F
// The sign of σ2 is compared with that of det A where the reference |σ2| exceeds the singular value
// tolerance by this factor: there an error within tolerance cannot flip it.
constexpr double kSignCheckMargin = 2.0;

constexpr int kFamilySize = 300;

// Row-major 3×3 in double; the matrices under test hold float values exactly.
using Mat3 = std::array<std::array<double, 3>, 3>;
using Vec3 = std::array<double, 3>;

// std430 layout of a GLSL mat3: three columns, each padded to a vec4.
struct Std430Mat3 {
  float columns[3][4];
};
static_assert(sizeof(Std430Mat3) == 48, "std430 mat3 is 3 vec4-aligned columns");

// std430 layout of `struct SvdResult { mat3 U; mat3 V; vec4 sigma; }` in the test kernel.
struct Std430SvdResult {
  Std430Mat3 U;
  Std430Mat3 V;
  float sigma[4];
};
static_assert(sizeof(Std430SvdResult) == 112, "std430 SvdResult: two mat3 and a vec4");

constexpr int kWorkGroupSize = 64;

// One invocation decomposes one matrix: reads matrices[i], writes results[i].
const char* const kSvdTestKernel = R"(#version 430 core
#include "common/svd3.glsl"

layout(local_size_x = WORK_GROUP_SIZE) in;

struct SvdResult {
  mat3 U;
  mat3 V;
  vec4 sigma;
};

layout(std430, binding = 0) readonly buffer Matrices { mat3 matrices[]; };
layout(std430, binding = 1) writeonly buffer Results { SvdResult results[]; };

uniform uint matrixCount;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= matrixCount) return;
  mat3 U;
  vec3 sigma;
  mat3 V;
  svd3(matrices[i], U, sigma, V);
  results[i] = SvdResult(U, V, vec4(sigma, 0.0));
}
)";

// ---- small double-precision linear algebra ----

Mat3 identity() { return {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}; }

Mat3 diagonal(const Vec3& d) { return {{{d[0], 0, 0}, {0, d[1], 0}, {0, 0, d[2]}}}; }

Mat3 multiply(const Mat3& a, const Mat3& b) {
  Mat3 c{};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      for (int col = 0; col < 3; ++col) c[r][col] += a[r][k] * b[k][col];
  return c;
}

Mat3 transpose(const Mat3& a) {
  Mat3 t{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) t[c][r] = a[r][c];
  return t;
}

Mat3 subtract(const Mat3& a, const Mat3& b) {
  Mat3 d{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d[r][c] = a[r][c] - b[r][c];
  return d;
}

double frobeniusNorm(const Mat3& a) {
  double sum = 0;
  for (const auto& row : a)
    for (double x : row) sum += x * x;
  return std::sqrt(sum);
}

double determinant(const Mat3& a) {
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

// The GPU sees float matrices; rounding first makes the reference decompose exactly what the GPU does.
Mat3 roundedToFloat(Mat3 a) {
  for (auto& row : a)
    for (double& x : row) x = static_cast<float>(x);
  return a;
}

// ---- matrices from a fixed seed ----

// Uniform in [lo, hi) from raw mt19937 output (fully specified by the standard, unlike the distributions),
// so every standard library generates the same matrices.
double uniform(std::mt19937& rng, double lo, double hi) { return lo + (hi - lo) * (rng() * 0x1p-32); }

Mat3 uniformMatrix(std::mt19937& rng, double lo, double hi) {
  Mat3 a{};
  for (auto& row : a)
    for (double& x : row) x = uniform(rng, lo, hi);
  return a;
}

// A rotation from a uniformly distributed unit quaternion (rejection sampling in the 4-ball).
Mat3 randomRotation(std::mt19937& rng) {
  double x, y, z, w, norm2;
  do {
    x = uniform(rng, -1, 1);
    y = uniform(rng, -1, 1);
    z = uniform(rng, -1, 1);
    w = uniform(rng, -1, 1);
    norm2 = x * x + y * y + z * z + w * w;
  } while (norm2 > 1 || norm2 < 1e-2);
  const double s = 1 / std::sqrt(norm2);
  x *= s, y *= s, z *= s, w *= s;
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

// R1 diag(sigma) R2 with random rotations, rounded to float.
Mat3 withSingularValues(std::mt19937& rng, const Vec3& sigma) {
  return roundedToFloat(multiply(multiply(randomRotation(rng), diagonal(sigma)), randomRotation(rng)));
}

double randomSign(std::mt19937& rng) { return (rng() & 1u) ? 1.0 : -1.0; }

// ±2^k, k in [-2, 2]: scaling a float by it is exact.
double randomPowerOfTwo(std::mt19937& rng) {
  const int exponent = static_cast<int>(rng() % 5) - 2;
  return randomSign(rng) * std::ldexp(1.0, exponent);
}

// ---- the double-precision reference ----

// Singular values of A, sorted decreasing, the last carrying the sign of det A. One-sided (Hestenes) Jacobi:
// rotate pairs of columns of A until all are orthogonal to double precision; the column norms are then the
// singular values with absolute error near 1e-16 ‖A‖, far below the float tolerances (and, unlike the
// square roots of the eigenvalues of AᵀA, also for tiny singular values).
Vec3 referenceSingularValues(const Mat3& a) {
  Mat3 w = a;
  const std::pair<int, int> pairs[] = {{0, 1}, {0, 2}, {1, 2}};
  bool rotated = true;
  for (int sweep = 0; sweep < 60 && rotated; ++sweep) {
    rotated = false;
    for (const auto& [i, j] : pairs) {
      double alpha = 0, beta = 0, gamma = 0;
      for (int r = 0; r < 3; ++r) {
        alpha += w[r][i] * w[r][i];
        beta += w[r][j] * w[r][j];
        gamma += w[r][i] * w[r][j];
      }
      if (std::abs(gamma) <= std::numeric_limits<double>::epsilon() * std::sqrt(alpha * beta)) continue;
      rotated = true;
      const double zeta = (beta - alpha) / (2 * gamma);
      const double t = std::copysign(1.0, zeta) / (std::abs(zeta) + std::hypot(1.0, zeta));
      const double c = 1 / std::sqrt(1 + t * t);
      const double s = c * t;
      for (int r = 0; r < 3; ++r) {
        const double wi = w[r][i], wj = w[r][j];
        w[r][i] = c * wi - s * wj;
        w[r][j] = s * wi + c * wj;
      }
    }
  }
  Vec3 sigma{};
  for (int c = 0; c < 3; ++c) sigma[c] = std::sqrt(w[0][c] * w[0][c] + w[1][c] * w[1][c] + w[2][c] * w[2][c]);
  std::sort(sigma.begin(), sigma.end(), [](double x, double y) { return x > y; });
  if (determinant(a) < 0) sigma[2] = -sigma[2];
  return sigma;
}

// ---- running the kernel ----

Std430Mat3 toStd430(const Mat3& a) {
  Std430Mat3 m{};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m.columns[c][r] = static_cast<float>(a[r][c]);
  return m;
}

Mat3 fromStd430(const Std430Mat3& m) {
  Mat3 a{};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) a[r][c] = m.columns[c][r];
  return a;
}

struct Svd {
  Mat3 U;
  Vec3 sigma;
  Mat3 V;
};

std::string describe(const Mat3& a) {
  std::ostringstream out;
  out.precision(9);
  out << "A = [";
  for (int r = 0; r < 3; ++r) out << a[r][0] << ' ' << a[r][1] << ' ' << a[r][2] << (r < 2 ? "; " : "]");
  return out.str();
}

// Largest value of one error measure over a family, and the matrix where it occurred.
struct WorstCase {
  double error = 0;
  std::size_t index = 0;

  void update(double value, std::size_t i) {
    if (!(value <= error)) {  // NaN counts as the worst
      error = value;
      index = i;
    }
  }
};

class GpuSvd : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    firn::test::glContext();
    ShaderLibrary library;
    library.add("test/svd_test.comp", kSvdTestKernel);
    ShaderOptions options;
    options.defines = {{"WORK_GROUP_SIZE", std::to_string(kWorkGroupSize)}};
    program_ = Program::compute(library, "test/svd_test.comp", options);
  }

  static void TearDownTestSuite() { program_ = Program(); }

  static std::vector<Svd> decomposeOnGpu(const std::vector<Mat3>& matrices) {
    std::vector<Std430Mat3> input;
    input.reserve(matrices.size());
    for (const Mat3& a : matrices) input.push_back(toStd430(a));
    const Buffer inputBuffer = Buffer::fromVector(input);
    const Buffer resultBuffer(matrices.size() * sizeof(Std430SvdResult));
    inputBuffer.bindStorage(0);
    resultBuffer.bindStorage(1);
    program_.use();
    program_.set("matrixCount", static_cast<unsigned>(matrices.size()));
    glDispatchCompute(static_cast<GLuint>((matrices.size() + kWorkGroupSize - 1) / kWorkGroupSize), 1, 1);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

    std::vector<Svd> results;
    for (const Std430SvdResult& r : resultBuffer.read<Std430SvdResult>(matrices.size())) {
      results.push_back({fromStd430(r.U), {r.sigma[0], r.sigma[1], r.sigma[2]}, fromStd430(r.V)});
    }
    return results;
  }

  // Decomposes `matrices` on the GPU, checks every result against the contract of svd3() and returns them.
  static std::vector<Svd> expectAccurateSvd(const std::vector<Mat3>& matrices) {
    std::vector<Svd> results = decomposeOnGpu(matrices);
    WorstCase reconstruction, orthogonality, determinantOfRotations, ordering, singularValues;
    std::size_t signsChecked = 0;
    for (std::size_t i = 0; i < matrices.size(); ++i) {
      const Mat3& a = matrices[i];
      const Svd& svd = results[i];
      const double scale = std::max(frobeniusNorm(a), 1e-30);  // the zero matrix must give zero exactly

      const Mat3 product = multiply(multiply(svd.U, diagonal(svd.sigma)), transpose(svd.V));
      reconstruction.update(frobeniusNorm(subtract(product, a)) / scale, i);

      orthogonality.update(frobeniusNorm(subtract(multiply(transpose(svd.U), svd.U), identity())), i);
      orthogonality.update(frobeniusNorm(subtract(multiply(transpose(svd.V), svd.V), identity())), i);
      determinantOfRotations.update(std::abs(determinant(svd.U) - 1), i);
      determinantOfRotations.update(std::abs(determinant(svd.V) - 1), i);

      const Vec3& s = svd.sigma;
      ordering.update(std::max({0.0, s[1] - s[0], std::abs(s[2]) - s[1], -s[1]}) / scale, i);

      const Vec3 reference = referenceSingularValues(a);
      for (int k = 0; k < 3; ++k) singularValues.update(std::abs(s[k] - reference[k]) / scale, i);

      if (std::abs(reference[2]) > kSignCheckMargin * kSingularValueTolerance * scale) {
        ++signsChecked;
        EXPECT_EQ(std::signbit(s[2]), std::signbit(reference[2]))
            << "sigma2 = " << s[2] << " has the wrong sign for det A = " << determinant(a) << ", " << describe(a);
      }
    }

    const auto report = [&](const char* name, const WorstCase& worst, double tolerance) {
      std::ostringstream inEpsilons;
      inEpsilons.precision(3);
      inEpsilons << worst.error / kFloatEpsilon;
      ::testing::Test::RecordProperty(std::string("max_") + name + "_in_float_eps", inEpsilons.str());
      EXPECT_LE(worst.error, tolerance) << name << " error " << worst.error << " (" << inEpsilons.str()
                                        << " float eps) at matrix " << worst.index << ": "
                                        << describe(matrices[worst.index]);
    };
    report("reconstruction", reconstruction, kReconstructionTolerance);
    report("orthogonality", orthogonality, kOrthogonalityTolerance);
    report("determinant", determinantOfRotations, kOrthogonalityTolerance);
    report("ordering", ordering, kOrderingTolerance);
    report("singular_values", singularValues, kSingularValueTolerance);
    ::testing::Test::RecordProperty("signs_checked", std::to_string(signsChecked));
    return results;
  }

  static Program program_;
};

Program GpuSvd::program_;

TEST_F(GpuSvd, DecomposesRandomMatrices) {
  std::mt19937 rng(1);
  std::vector<Mat3> matrices;
  for (int i = 0; i < kFamilySize; ++i) matrices.push_back(roundedToFloat(uniformMatrix(rng, -1, 1)));
  expectAccurateSvd(matrices);
}

// Deformation gradients near I are the common case in snow: singular values within 1e-3 of each other.
TEST_F(GpuSvd, DecomposesNearIdentityMatrices) {
  std::mt19937 rng(2);
  std::vector<Mat3> matrices;
  for (int i = 0; i < kFamilySize; ++i) {
    Mat3 a = identity();
    const Mat3 noise = uniformMatrix(rng, -1e-3, 1e-3);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a[r][c] += noise[r][c];
    matrices.push_back(roundedToFloat(a));
  }
  expectAccurateSvd(matrices);
}

// One singular value 1e-6 of the largest, the determinant of either sign.
TEST_F(GpuSvd, DecomposesNearSingularMatrices) {
  std::mt19937 rng(3);
  std::vector<Mat3> matrices;
  for (int i = 0; i < kFamilySize; ++i) {
    const double sigma0 = uniform(rng, 0.5, 2);
    const double sigma1 = sigma0 * uniform(rng, 0.1, 1);
    matrices.push_back(withSingularValues(rng, {sigma0, sigma1, randomSign(rng) * 1e-6 * sigma0}));
  }
  expectAccurateSvd(matrices);
}

// Exactly rank 2 (one column a power-of-two multiple of another) and exactly rank 1 (every column a
// power-of-two multiple of one vector), in float; transposed half the time; and the zero matrix.
TEST_F(GpuSvd, DecomposesRankDeficientMatrices) {
  std::mt19937 rng(4);
  std::vector<Mat3> matrices{Mat3{}};
  for (int i = 0; i < kFamilySize; ++i) {
    Mat3 a = roundedToFloat(uniformMatrix(rng, -1, 1));
    if (i % 2 == 0) {
      const int dependent = static_cast<int>(rng() % 3);
      const int source = (dependent + 1) % 3;
      const double multiple = randomPowerOfTwo(rng);
      for (int r = 0; r < 3; ++r) a[r][dependent] = multiple * a[r][source];
    } else {
      const Vec3 u{a[0][0], a[1][0], a[2][0]};
      for (int c = 0; c < 3; ++c) {
        const double multiple = randomPowerOfTwo(rng);
        for (int r = 0; r < 3; ++r) a[r][c] = multiple * u[r];
      }
    }
    matrices.push_back(rng() & 1u ? transpose(a) : a);
  }
  expectAccurateSvd(matrices);
}

// det A < 0: random matrices with one row negated as needed, near-reflections I − 2nnᵀ + 1e-3 noise, and
// flattened inverted ones. The smallest singular value must come out negative, U and V still rotations.
TEST_F(GpuSvd, DecomposesInvertedMatricesWithNegativeSmallestSingularValue) {
  std::mt19937 rng(5);
  std::vector<Mat3> matrices;
  for (int i = 0; i < kFamilySize; ++i) {
    Mat3 a{};
    if (i % 3 == 0) {
      a = roundedToFloat(uniformMatrix(rng, -1, 1));
      if (determinant(a) > 0) a[0] = {-a[0][0], -a[0][1], -a[0][2]};
    } else if (i % 3 == 1) {
      const Mat3 rotation = randomRotation(rng);
      const Vec3 n{rotation[0][0], rotation[1][0], rotation[2][0]};
      const Mat3 noise = uniformMatrix(rng, -1e-3, 1e-3);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) a[r][c] = (r == c ? 1.0 : 0.0) - 2 * n[r] * n[c] + noise[r][c];
      a = roundedToFloat(a);
    } else {
      const double sigma0 = uniform(rng, 0.5, 2);
      a = withSingularValues(rng, {sigma0, sigma0 * uniform(rng, 0.3, 1), -sigma0 * uniform(rng, 0.01, 0.3)});
    }
    ASSERT_LT(determinant(a), 0) << describe(a);
    matrices.push_back(a);
  }
  const std::vector<Svd> results = expectAccurateSvd(matrices);
  for (std::size_t i = 0; i < matrices.size(); ++i) {
    EXPECT_LT(results[i].sigma[2], 0) << describe(matrices[i]);
  }
}

// Diagonal matrices in any order and with any signs (the sort and the sign bookkeeping alone), and signed
// permutation matrices: exact rotations and reflections.
TEST_F(GpuSvd, DecomposesDiagonalAndSignedPermutationMatrices) {
  std::mt19937 rng(6);
  std::vector<Mat3> matrices;
  for (int i = 0; i < kFamilySize; ++i) {
    matrices.push_back(roundedToFloat(diagonal({uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)})));
  }
  const std::array<int, 3> permutations[] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& permutation : permutations) {
    for (unsigned signs = 0; signs < 8; ++signs) {
      Mat3 a{};
      for (int r = 0; r < 3; ++r) a[r][permutation[r]] = (signs >> r) & 1u ? -1.0 : 1.0;
      matrices.push_back(a);
    }
  }
  expectAccurateSvd(matrices);
}

// Two or three singular values equal before rounding to float, where the singular vectors are (nearly) not
// unique: (s, s, t), (s, t, t) and scaled rotations (s, s, s), either sign of det; and exact multiples of I.
TEST_F(GpuSvd, DecomposesMatricesWithRepeatedSingularValues) {
  std::mt19937 rng(7);
  std::vector<Mat3> matrices;
  for (int i = 0; i < kFamilySize; ++i) {
    const double s = uniform(rng, 0.5, 2);
    const double t = s * uniform(rng, 0.1, 1);
    const double sign = randomSign(rng);
    const Vec3 sigma = i % 3 == 0 ? Vec3{s, s, sign * t} : i % 3 == 1 ? Vec3{s, t, sign * t} : Vec3{s, s, sign * s};
    matrices.push_back(withSingularValues(rng, sigma));
  }
  for (int k = -2; k <= 2; ++k) {
    const double s = std::ldexp(1.0, k);
    matrices.push_back(diagonal({s, s, s}));
  }
  expectAccurateSvd(matrices);
}

}  // namespace
