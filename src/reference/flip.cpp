// LDR-FLIP, following the paper's pipeline (Andersson et al. 2020):
//   colour:  sRGB -> linear RGB -> XYZ -> YCxCz (linear opponent space) -> per-channel CSF filter
//            -> linear RGB clamped to [0,1] -> CIELAB -> Hunt adjustment -> HyAB distance
//            -> ^qc -> compressed to [0,1] with (cmax, pc, pt)
//   feature: normalised achromatic Y of the unfiltered images -> edge (1st derivative of
//            Gaussian) and point (2nd derivative) detectors in x and y -> difference of the
//            response magnitudes -> ^qf
//   final:   Ec ^ (1 - Ef)
// Constants (all from the paper; the authors' public reference code uses the same values):
//   CSFs as Gaussian sums in the spatial domain, s(r) = sum_i a_i sqrt(pi/b_i) exp(-pi² r²/b_i)
//   with r in degrees: achromatic a1=1, b1=0.0047; red-green a1=1, b1=0.0053; blue-yellow
//   a1=34.1, b1=0.04, a2=13.5, b2=0.025; every kernel normalised to sum 1; radius
//   ceil(3 sqrt(b_max/(2 pi²)) ppd) with b_max = 0.04 (3 standard deviations of the widest term).
//   qc = 0.7, pc = 0.4, pt = 0.95; cmax = HyAB(Hunt(Lab(green)), Hunt(Lab(blue)))^qc.
//   Feature filters: peak-to-trough width w = 0.082 degrees = 2 sigma, so sigma = 0.5 w ppd
//   pixels, radius ceil(3 sigma); positive weights normalised to sum 1 and negative weights to
//   sum -1; qf = 0.5; the feature difference is divided by sqrt(2) before ^qf.
//   Borders replicate the edge pixel.
#include "reference/flip.h"
#include "base/numbers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>

#include "base/errors.h"

namespace hb {

namespace {

constexpr double kQc = 0.7, kPc = 0.4, kPt = 0.95, kQf = 0.5;
constexpr double kFeatureWidthDeg = 0.082;

struct GaussianTerm {
  double a, b;  // weight and scale of a * sqrt(pi/b) * exp(-pi² r² / b)
};
constexpr std::array<GaussianTerm, 1> kCsfAchromatic = {{{1.0, 0.0047}}};
constexpr std::array<GaussianTerm, 1> kCsfRedGreen = {{{1.0, 0.0053}}};
constexpr std::array<GaussianTerm, 2> kCsfBlueYellow = {{{34.1, 0.04}, {13.5, 0.025}}};
constexpr double kCsfMaxB = 0.04;

// A single-channel float image.
struct Plane {
  uint32_t width = 0, height = 0;
  std::vector<float> v;
  Plane(uint32_t w, uint32_t h) : width(w), height(h), v(size_t(w) * h, 0.0f) {}
};

using Kernel1D = std::vector<double>;  // 2r+1 taps, tap i applies to offset i - r

// Correlation with kx along x, then ky along y; edge pixels replicate (clamp-to-edge). For a
// separable 2D kernel kx(x)ky(y) this equals the 2D correlation with replicated borders exactly.
Plane convolveSeparable(const Plane& in, const Kernel1D& kx, const Kernel1D& ky) {
  const int w = int(in.width), h = int(in.height);
  const int rx = int(kx.size() / 2), ry = int(ky.size() / 2);
  Plane tmp(in.width, in.height), out(in.width, in.height);
  std::vector<float> padded(size_t(w + 2 * rx));
  for (int y = 0; y < h; ++y) {
    const float* row = &in.v[size_t(y) * w];
    for (int x = -rx; x < w + rx; ++x) padded[size_t(x + rx)] = row[std::clamp(x, 0, w - 1)];
    float* dst = &tmp.v[size_t(y) * w];
    for (int x = 0; x < w; ++x) {
      double sum = 0;
      for (size_t i = 0; i < kx.size(); ++i) sum += kx[i] * padded[size_t(x) + i];
      dst[x] = float(sum);
    }
  }
  std::vector<double> acc(static_cast<size_t>(w));
  for (int y = 0; y < h; ++y) {
    std::fill(acc.begin(), acc.end(), 0.0);
    for (int i = 0; i < int(ky.size()); ++i) {
      const float* src = &tmp.v[size_t(std::clamp(y + i - ry, 0, h - 1)) * w];
      const double k = ky[size_t(i)];
      for (int x = 0; x < w; ++x) acc[size_t(x)] += k * src[x];
    }
    float* dst = &out.v[size_t(y) * w];
    for (int x = 0; x < w; ++x) dst[x] = float(acc[size_t(x)]);
  }
  return out;
}

int csfRadius(double ppd) { return int(std::ceil(3.0 * std::sqrt(kCsfMaxB / (2.0 * kPi * kPi)) * ppd)); }
double featureSigma(double ppd) { return 0.5 * kFeatureWidthDeg * ppd; }
int featureRadius(double ppd) { return int(std::ceil(3.0 * featureSigma(ppd))); }

// One CSF term exp(-pi² x²/b) sampled at pixel offsets (x in degrees = offset/ppd), unnormalised.
Kernel1D csfGaussian(double b, double ppd, int radius) {
  Kernel1D k(size_t(2 * radius + 1));
  for (int i = -radius; i <= radius; ++i) {
    const double xDeg = i / ppd;
    k[size_t(i + radius)] = std::exp(-kPi * kPi * xDeg * xDeg / b);
  }
  return k;
}

double sum(const Kernel1D& k) { return std::accumulate(k.begin(), k.end(), 0.0); }

Kernel1D normalised(Kernel1D k) {
  const double s = sum(k);
  for (double& v : k) v /= s;
  return k;
}

// Filters `in` with a CSF that is a sum of Gaussian terms. Each 2D term is the separable product
// g(x)g(y) weighted a*sqrt(pi/b); the sum of the 2D kernel is sum_i a_i sqrt(pi/b_i) S_i² with
// S_i the 1D sum, so the normalised 2D kernel is sum_i alpha_i (g_i/S_i ⊗ g_i/S_i) with
// alpha_i = a_i sqrt(pi/b_i) S_i² / total.
template <size_t N>
Plane csfFilter(const Plane& in, const std::array<GaussianTerm, N>& terms, double ppd) {
  const int radius = csfRadius(ppd);
  std::array<Kernel1D, N> kernels;
  std::array<double, N> alpha{};
  double total = 0;
  for (size_t i = 0; i < N; ++i) {
    kernels[i] = csfGaussian(terms[i].b, ppd, radius);
    const double s = sum(kernels[i]);
    alpha[i] = terms[i].a * std::sqrt(kPi / terms[i].b) * s * s;
    total += alpha[i];
    kernels[i] = normalised(std::move(kernels[i]));
  }
  Plane out(in.width, in.height);
  for (size_t i = 0; i < N; ++i) {
    const Plane part = convolveSeparable(in, kernels[i], kernels[i]);
    const float weight = float(alpha[i] / total);
    for (size_t p = 0; p < out.v.size(); ++p) out.v[p] += weight * part.v[p];
  }
  return out;
}

// The feature detectors' 2D kernels are h(x)g(y) with g(y) = exp(-y²/(2 sigma²)) > 0, so the
// sum of their positive (negative) weights is (sum of h's positive (negative) weights) * sum(g):
// normalising h's two signs separately and g to sum 1 gives the paper's normalisation exactly.
struct FeatureKernels {
  Kernel1D gauss, edge, point;
};

FeatureKernels featureKernels(double ppd) {
  const double sigma = featureSigma(ppd);
  const int radius = featureRadius(ppd);
  FeatureKernels k;
  for (int i = -radius; i <= radius; ++i) {
    const double x = i;
    const double g = std::exp(-x * x / (2.0 * sigma * sigma));
    k.gauss.push_back(g);
    k.edge.push_back(-x * g);                                // d/dx of the Gaussian (up to scale)
    k.point.push_back((x * x / (sigma * sigma) - 1.0) * g);  // d²/dx² of the Gaussian (up to scale)
  }
  k.gauss = normalised(std::move(k.gauss));
  for (Kernel1D* h : {&k.edge, &k.point}) {
    double pos = 0, neg = 0;
    for (double v : *h) (v > 0 ? pos : neg) += v;
    HB_ASSERT(pos > 0 && neg < 0);  // radius = ceil(3 sigma) > sigma keeps both signs present
    for (double& v : *h) v = v > 0 ? v / pos : v / -neg;
  }
  return k;
}

// sRGB primaries with D65 white (IEC 61966-2-1), linear RGB -> XYZ, rows X, Y, Z (exact
// rationals of the standard's derivation).
constexpr double kRgbToXyz[3][3] = {{10135552.0 / 24577794, 8788810.0 / 24577794, 4435075.0 / 24577794},
                                    {2613072.0 / 12288897, 8788810.0 / 12288897, 887015.0 / 12288897},
                                    {1425312.0 / 73733382, 8788810.0 / 73733382, 70074185.0 / 73733382}};

struct Mat3 {
  double m[3][3];
  std::array<double, 3> operator*(const std::array<double, 3>& v) const {
    return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
  }
};

Mat3 inverse(const double (&a)[3][3]) {
  const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                     a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                     a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  Mat3 r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      // cofactor of a[j][i] (transpose for the adjugate)
      const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
      r.m[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
    }
  return r;
}

struct ColourSpace {
  Mat3 rgbToXyz{}, xyzToRgb{};
  std::array<double, 3> white{};  // XYZ of linear RGB (1,1,1): the reference white
  std::array<double, 256> srgbToLinear{};
  ColourSpace() {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) rgbToXyz.m[i][j] = kRgbToXyz[i][j];
    xyzToRgb = inverse(kRgbToXyz);
    white = rgbToXyz * std::array<double, 3>{1, 1, 1};
    for (int i = 0; i < 256; ++i) srgbToLinear[size_t(i)] = hb::srgbToLinear(i / 255.0);
  }

  // YCxCz (the paper's linearised CIELAB): Y' = 116 y - 16, Cx = 500 (x - y), Cz = 200 (y - z)
  // with x, y, z the white-normalised XYZ.
  std::array<double, 3> linearRgbToYcxcz(const std::array<double, 3>& rgb) const {
    const auto xyz = rgbToXyz * rgb;
    const double x = xyz[0] / white[0], y = xyz[1] / white[1], z = xyz[2] / white[2];
    return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
  }
  std::array<double, 3> ycxczToLinearRgb(const std::array<double, 3>& c) const {
    const double y = (c[0] + 16.0) / 116.0;
    const double x = y + c[1] / 500.0, z = y - c[2] / 200.0;
    return xyzToRgb * std::array<double, 3>{x * white[0], y * white[1], z * white[2]};
  }
  // CIELAB (CIE 15:2004) followed by the Hunt adjustment a' = 0.01 L a, b' = 0.01 L b, which
  // lowers chroma differences in dark colours as the Hunt effect does.
  std::array<double, 3> linearRgbToHuntLab(const std::array<double, 3>& rgb) const {
    const auto xyz = rgbToXyz * rgb;
    constexpr double kDelta = 6.0 / 29.0;
    const auto f = [](double t) {
      return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3.0 * kDelta * kDelta) + 4.0 / 29.0;
    };
    const double fx = f(xyz[0] / white[0]), fy = f(xyz[1] / white[1]), fz = f(xyz[2] / white[2]);
    const double l = 116.0 * fy - 16.0, a = 500.0 * (fx - fy), b = 200.0 * (fy - fz);
    return {l, 0.01 * l * a, 0.01 * l * b};
  }
};

const ColourSpace& colourSpace() {
  static const ColourSpace cs;
  return cs;
}

// HyAB (Abasi et al. 2020): |dL| + Euclidean distance in (a, b).
double hyab(const std::array<double, 3>& p, const std::array<double, 3>& q) {
  return std::abs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]);
}

// What each image contributes to the error: Hunt-adjusted Lab after the CSF, and the magnitudes
// of its edge and point responses.
struct Prepared {
  Plane l, a, b, edge, point;
  Prepared(uint32_t w, uint32_t h) : l(w, h), a(w, h), b(w, h), edge(w, h), point(w, h) {}
};

Prepared prepare(const ImageRGBA8& img, double ppd, const FeatureKernels& fk) {
  const ColourSpace& cs = colourSpace();
  const size_t n = size_t(img.width) * img.height;
  Plane y(img.width, img.height), cx(img.width, img.height), cz(img.width, img.height);
  Plane yNorm(img.width, img.height);
  for (size_t i = 0; i < n; ++i) {
    const std::array<double, 3> rgb = {cs.srgbToLinear[img.px[4 * i]], cs.srgbToLinear[img.px[4 * i + 1]],
                                       cs.srgbToLinear[img.px[4 * i + 2]]};
    const auto c = cs.linearRgbToYcxcz(rgb);
    y.v[i] = float(c[0]);
    cx.v[i] = float(c[1]);
    cz.v[i] = float(c[2]);
    yNorm.v[i] = float((c[0] + 16.0) / 116.0);  // achromatic channel in [0,1] for the features
  }

  const Plane yf = csfFilter(y, kCsfAchromatic, ppd);
  const Plane cxf = csfFilter(cx, kCsfRedGreen, ppd);
  const Plane czf = csfFilter(cz, kCsfBlueYellow, ppd);
  Prepared out(img.width, img.height);
  for (size_t i = 0; i < n; ++i) {
    auto rgb = cs.ycxczToLinearRgb({yf.v[i], cxf.v[i], czf.v[i]});
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);  // the filtered colour may leave the gamut
    const auto lab = cs.linearRgbToHuntLab(rgb);
    out.l.v[i] = float(lab[0]);
    out.a.v[i] = float(lab[1]);
    out.b.v[i] = float(lab[2]);
  }

  const Plane edgeX = convolveSeparable(yNorm, fk.edge, fk.gauss);
  const Plane edgeY = convolveSeparable(yNorm, fk.gauss, fk.edge);
  const Plane pointX = convolveSeparable(yNorm, fk.point, fk.gauss);
  const Plane pointY = convolveSeparable(yNorm, fk.gauss, fk.point);
  for (size_t i = 0; i < n; ++i) {
    out.edge.v[i] = std::hypot(edgeX.v[i], edgeY.v[i]);
    out.point.v[i] = std::hypot(pointX.v[i], pointY.v[i]);
  }
  return out;
}

// Linear interpolation between closest ranks of sorted values, p in [0,1].
double percentileSorted(const std::vector<float>& sorted, double p) {
  const double pos = p * double(sorted.size() - 1);
  const size_t lo = size_t(std::floor(pos));
  const size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (pos - double(lo)) * (double(sorted[hi]) - sorted[lo]);
}

}  // namespace

int flipSupportRadius(double ppd) { return std::max(csfRadius(ppd), featureRadius(ppd)); }

FlipResult ldrFlip(const ImageRGBA8& reference, const ImageRGBA8& test, double ppd) {
  if (reference.width != test.width || reference.height != test.height)
    throw InputError("FLIP: reference is " + std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                     " but test is " + std::to_string(test.width) + "x" + std::to_string(test.height) +
                     "; render both at the same resolution");
  HB_ASSERT(std::isfinite(ppd) && ppd > 0);
  HB_ASSERT(reference.width > 0 && reference.height > 0);
  HB_ASSERT(reference.px.size() == size_t(reference.width) * reference.height * 4);
  HB_ASSERT(test.px.size() == reference.px.size());

  const FeatureKernels fk = featureKernels(ppd);
  const Prepared ref = prepare(reference, ppd, fk);
  const Prepared tst = prepare(test, ppd, fk);

  const ColourSpace& cs = colourSpace();
  const double cmax = std::pow(hyab(cs.linearRgbToHuntLab({0, 1, 0}), cs.linearRgbToHuntLab({0, 0, 1})), kQc);
  const double pcCmax = kPc * cmax;

  FlipResult result;
  const size_t n = size_t(reference.width) * reference.height;
  result.errorMap = ImageF{reference.width, reference.height, 1, std::vector<float>(n)};
  double total = 0;
  for (size_t i = 0; i < n; ++i) {
    const double colourDistance =
        std::pow(hyab({ref.l.v[i], ref.a.v[i], ref.b.v[i]}, {tst.l.v[i], tst.a.v[i], tst.b.v[i]}), kQc);
    // Compress: [0, pc*cmax) -> [0, pt) linearly, [pc*cmax, cmax] -> [pt, 1].
    const double ec = colourDistance < pcCmax ? kPt * colourDistance / pcCmax
                                              : kPt + (colourDistance - pcCmax) / (cmax - pcCmax) * (1.0 - kPt);
    const double featureDiff =
        std::max(std::abs(double(ref.edge.v[i]) - tst.edge.v[i]), std::abs(double(ref.point.v[i]) - tst.point.v[i]));
    const double ef = std::pow(featureDiff / std::numbers::sqrt2, kQf);
    // The paper takes green-blue (cmax) as the largest distance in the gamut, so the clamps only
    // absorb round-off.
    const double e = std::clamp(std::pow(std::min(ec, 1.0), 1.0 - std::min(ef, 1.0)), 0.0, 1.0);
    result.errorMap.px[i] = float(e);
    total += e;
  }
  std::vector<float> sorted = result.errorMap.px;
  std::sort(sorted.begin(), sorted.end());
  result.mean = total / double(n);
  result.p50 = percentileSorted(sorted, 0.50);
  result.p95 = percentileSorted(sorted, 0.95);
  result.max = sorted.back();
  return result;
}

}  // namespace hb
