#include "clipray/check/MatrixReading.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "clipray/math/Projections.hpp"

namespace clipray {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The error model (docs/check.md, "Uncertainty"). Rounding x to a float of unit roundoff u errs
// uniformly within half an ulp, u |x| / m for x's binary mantissa m in [1, 2); over mantissas
// spread as real data's are (Benford: density 1 / (m ln 2)) the mean square is
// u^2 x^2 E[1/m^2] / 3 = u^2 x^2 / (8 ln 2): standard deviation 0.4247 u |x| per rounding.
// kRoundings is how many are counted per entry (P * V's product and sum);
// kCoverage is how many standard deviations of the propagated error a stated "+-" spans. Both are
// checked against a Monte Carlo of float32 constructions in tests/unit/CheckUncertaintyTest.cpp.
const double kPerRounding = 1.0 / std::sqrt(8.0 * std::log(2.0));
constexpr double kRoundings = 2.0;
constexpr double kCoverage = 4.5;

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// Angle between two lines (either sign of either vector).
double lineAngle(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), std::abs(glm::dot(a, b)));
}

// The part of the line a's unit direction across the unit vector b (sign taken along b): its
// length is the sine of lineAngle(a, b). An angle near 0 is the length of this vector, whose
// change under an error is what the error does to the angle; the length's own change is not
// (an error larger than the vector turns it round and changes its length by little).
glm::dvec3 across(const glm::dvec3& a, const glm::dvec3& b) {
  glm::dvec3 unit = glm::normalize(a);
  if (glm::dot(unit, b) < 0.0) unit = -unit;
  return unit - glm::dot(unit, b) * b;
}

bool isFloat(double v) {
  return static_cast<double>(static_cast<float>(v)) == v;
}

// Within the rounding of a float32 printed with %.9g (which round-trips every float32).
bool isNineDigitFloat(double v) {
  const double f = static_cast<float>(v);
  return std::abs(v - f) <= 5e-9 * std::abs(f);
}

// The figures of a matrix as plain numbers; readMatrix perturbs the entries and reads them again.
struct Figures {
  double a = kNaN, b = kNaN;
  glm::dvec3 eye{kNaN};
  glm::dvec3 forward{0.0};
  double nearNo = kNaN, nearZo = kNaN, atOne = kNaN;  // distances at z_ndc = -1, 0, 1
  double obliqueNo = 0.0, obliqueZo = 0.0, obliqueReversed = 0.0, offAxis = 0.0;
  // The angles' vectors (across): an angle's error is taken from its vector's change.
  glm::dvec3 obliqueNoAcross{0.0}, obliqueZoAcross{0.0}, obliqueReversedAcross{0.0},
      offAxisAcross{0.0};
  double handedness = 0.0, upY = 0.0, fovY = 0.0, fovX = 0.0, extentX = 0.0, extentY = 0.0;
};

glm::dvec3 xyz(const glm::dvec4& v) {
  return glm::dvec3(v);
}

Figures perspectiveFigures(const glm::dmat4& m) {
  Figures f;
  const glm::dvec4 x = matrixRow(m, 0), y = matrixRow(m, 1), z = matrixRow(m, 2),
                   w = matrixRow(m, 3);
  const double wLength = glm::length(xyz(w));
  f.forward = xyz(w) / wLength;
  // The eye: x = y = w = 0 (rows 0, 1 and 3), independent of row 2, which oblique clipping edits.
  const glm::dmat3 rows = glm::transpose(glm::dmat3(xyz(x), xyz(y), xyz(w)));
  f.eye = glm::inverse(rows) * -glm::dvec3(x.w, y.w, w.w);
  f.a = glm::dot(z, glm::dvec4(f.eye, 1.0)) / wLength;
  f.b = glm::dot(xyz(z), f.forward) / wLength;
  const auto distanceAt = [&](double zNdc) {
    const double s = f.a / (zNdc - f.b);
    return std::isfinite(s) && s > 0.0 ? s : kNaN;
  };
  f.nearNo = distanceAt(-1.0);
  f.nearZo = distanceAt(0.0);
  f.atOne = distanceAt(1.0);
  f.obliqueNo = lineAngle(xyz(z) + xyz(w), f.forward);
  f.obliqueZo = lineAngle(xyz(z), f.forward);
  f.obliqueReversed = lineAngle(xyz(z) - xyz(w), f.forward);
  f.obliqueNoAcross = across(xyz(z) + xyz(w), f.forward);
  f.obliqueZoAcross = across(xyz(z), f.forward);
  f.obliqueReversedAcross = across(xyz(z) - xyz(w), f.forward);
  // The line of sight through NDC (x', y'): the planes x = x' w and y = y' w cross along it; its
  // sign is the one along which w grows (in front of the eye), whatever the near plane does.
  const auto sight = [&](double xn, double yn) {
    const glm::dvec3 d = glm::cross(xyz(x) - xn * xyz(w), xyz(y) - yn * xyz(w));
    return glm::normalize(glm::dot(d, xyz(w)) < 0.0 ? -d : d);
  };
  f.offAxis = angleBetween(sight(0, 0), f.forward);
  f.offAxisAcross = across(sight(0, 0), f.forward);
  // The camera's own right and up axes: clip x and y grow along the parts of rows 0 and 1
  // across the view (an off-axis shear only adds a multiple of the forward axis to them).
  const glm::dvec3 right = glm::normalize(xyz(x) - glm::dot(xyz(x), f.forward) * f.forward);
  const glm::dvec3 up = glm::normalize(xyz(y) - glm::dot(xyz(y), f.forward) * f.forward);
  f.handedness = glm::dot(glm::cross(right, up), f.forward);
  f.upY = up.y;
  f.fovY = angleBetween(sight(0, -1), sight(0, 1)) * 180.0 / kPi;
  f.fovX = angleBetween(sight(-1, 0), sight(1, 0)) * 180.0 / kPi;
  return f;
}

Figures orthographicFigures(const glm::dmat4& m, const glm::dvec3& anchor) {
  Figures f;
  const glm::dvec4 x = matrixRow(m, 0), y = matrixRow(m, 1), z = matrixRow(m, 2),
                   w = matrixRow(m, 3);
  // Parallel rays run along the line x = y = 0; forward is where depth grows.
  const glm::dvec3 d = glm::normalize(glm::cross(xyz(x), xyz(y)));
  f.forward = glm::dot(d, xyz(z)) < 0.0 ? -d : d;
  const double zRate = glm::dot(xyz(z), f.forward);
  const double zAtAnchor = glm::dot(z, glm::dvec4(anchor, 1.0));
  const auto offsetAt = [&](double zNdc) { return (zNdc * w.w - zAtAnchor) / zRate; };
  f.nearNo = offsetAt(-1.0);
  f.nearZo = offsetAt(0.0);
  f.atOne = offsetAt(1.0);
  f.obliqueNo = f.obliqueZo = f.obliqueReversed = lineAngle(xyz(z), f.forward);
  f.obliqueNoAcross = f.obliqueZoAcross = f.obliqueReversedAcross = across(xyz(z), f.forward);
  const glm::dvec3 xPerp = xyz(x) - glm::dot(xyz(x), f.forward) * f.forward;
  const glm::dvec3 yPerp = xyz(y) - glm::dot(xyz(y), f.forward) * f.forward;
  f.extentX = 2.0 * std::abs(w.w) / glm::length(xPerp);
  f.extentY = 2.0 * std::abs(w.w) / glm::length(yPerp);
  const glm::dvec3 right = glm::normalize(xPerp), up = glm::normalize(yPerp);
  f.handedness = glm::dot(glm::cross(right, up), f.forward);
  f.upY = up.y;
  return f;
}

Figures figuresOf(const glm::dmat4& m, bool perspective, const glm::dvec3& anchor) {
  return perspective ? perspectiveFigures(m) : orthographicFigures(m, anchor);
}

// |a - b| where NaN on one side only counts as an unbounded change (a reading that stops existing
// under a rounding error is not known), and NaN on both as none.
double change(double a, double b) {
  if (std::isnan(a) && std::isnan(b)) return 0.0;
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::infinity();
  return std::abs(a - b);
}

}  // namespace

double EntryPrecision::unitRoundoff() const {
  return arithmetic == Arithmetic::Float32 ? std::ldexp(1.0, -24) : std::ldexp(1.0, -53);
}

double EntryPrecision::decimalRelative() const {
  return decimalDigits > 0 ? 0.5 * std::pow(10.0, 1 - decimalDigits) : 0.0;
}

std::string EntryPrecision::description() const {
  const std::string base = arithmetic == Arithmetic::Float32 ? "float32"
                           : storedAsFloat32                 ? "double stored as float32"
                                                             : "double";
  if (decimalDigits == 0) return base;
  return base + " as " + std::to_string(decimalDigits) + "-digit decimals";
}

std::string shownReading(const Uncertain& reading) {
  int digits = 6;
  if (reading.error > 0.0 && reading.value != 0.0) {
    // An error that swamps the value (or an infinite one) leaves one digit; clamped in double,
    // since the logarithm may be infinite or NaN.
    const double resolvable = std::abs(reading.value) / reading.error;
    const double wanted = std::ceil(std::log10(resolvable)) + 1.0;
    digits = wanted >= 6.0 ? 6 : wanted >= 1.0 ? static_cast<int>(wanted) : 1;
  }
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, reading.value + 0.0);
  return buffer;
}

int significantDigits(double v, double relativeTolerance) {
  if (v == 0.0) return 1;
  for (int digits = 1; digits <= 17; ++digits) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.*e", digits - 1, v);
    if (std::abs(std::strtod(buffer, nullptr) - v) <= relativeTolerance * std::abs(v))
      return digits;
  }
  return 18;
}

double nearestRoundNumber(double v) {
  if (v == 0.0 || !std::isfinite(v)) return v;
  // Two significant digits, rounded in decimal (0.0999 carries into 0.1).
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.1e", v);
  return std::strtod(buffer, nullptr);
}

EntryPrecision detectEntryPrecision(const std::vector<glm::dmat4>& matrices) {
  bool allFloat = true, allNineDigitFloat = true;
  int mostDigits = 0;
  for (const glm::dmat4& m : matrices) {
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) {
        const double v = m[c][r];
        allFloat = allFloat && isFloat(v);
        allNineDigitFloat = allNineDigitFloat && isNineDigitFloat(v);
        if (v != 0.0) mostDigits = std::max(mostDigits, significantDigits(v, 0.0));
      }
    }
  }
  EntryPrecision precision;
  if (allFloat || allNineDigitFloat) {
    precision.arithmetic = EntryPrecision::Arithmetic::Float32;
    precision.storedAsFloat32 = true;
  } else if (mostDigits >= 16) {
    precision.arithmetic = EntryPrecision::Arithmetic::Double;
  } else {
    // Short decimals say nothing of the arithmetic behind them: assume float32, the coarser.
    precision.arithmetic = EntryPrecision::Arithmetic::Float32;
    precision.decimalDigits = mostDigits;
  }
  return precision;
}

glm::dvec3 translationAnchor(const glm::dmat4& clipFromWorld) {
  const glm::dvec4 x = matrixRow(clipFromWorld, 0), y = matrixRow(clipFromWorld, 1),
                   w = matrixRow(clipFromWorld, 3);
  const glm::dmat3 rows = glm::transpose(glm::dmat3(xyz(x), xyz(y), xyz(w)));
  if (glm::length(xyz(w)) > 0.0 && std::abs(glm::determinant(rows)) > 0.0) {
    const glm::dvec3 eye = glm::inverse(rows) * -glm::dvec3(x.w, y.w, w.w);
    if (std::isfinite(eye.x) && std::isfinite(eye.y) && std::isfinite(eye.z)) return eye;
  }
  const glm::dvec4 centre = glm::inverse(clipFromWorld) * glm::dvec4(0, 0, 0, 1);
  return glm::dvec3(centre) / centre.w;
}

double decimalHalfUnit(double value, int digits) {
  if (digits <= 0 || value == 0.0 || !std::isfinite(value)) return 0.0;
  // Half a unit in the d-th significant digit of the value as printed (%.{d-1}e shows the decade
  // the printed value has, also where rounding carried into the next one).
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.*e", digits - 1, value);
  const char* exponent = std::strchr(buffer, 'e');
  const int decade = exponent ? std::atoi(exponent + 1) : 0;
  return 0.5 * std::pow(10.0, decade - digits + 1);
}

EntryErrors entryErrors(const glm::dmat4& m, const EntryPrecision& precision,
                        const glm::dvec3& anchor) {
  // kRoundings roundings at the magnitude of the terms, each of standard deviation kPerRounding u.
  const double perMagnitude = precision.unitRoundoff() * kPerRounding * std::sqrt(kRoundings);
  const glm::dvec3 wXyz = xyz(matrixRow(m, 3));
  // The axis the rows are split along: w's (perspective), else the direction depth runs along.
  glm::dvec3 axis = wXyz;
  if (!(glm::length(axis) > 0.0)) axis = glm::cross(xyz(matrixRow(m, 0)), xyz(matrixRow(m, 1)));
  axis = glm::length(axis) > 0.0 ? glm::normalize(axis) : glm::dvec3(0.0, 0.0, 1.0);
  const double eyeAlong = glm::dot(anchor, axis);
  const double eyeAcross = glm::length(anchor - eyeAlong * axis);
  const double storedRounding =
      precision.storedAsFloat32 && precision.arithmetic == EntryPrecision::Arithmetic::Double
          ? std::ldexp(1.0, -24) * kPerRounding
          : 0.0;
  EntryErrors errors;
  for (int r = 0; r < 4; ++r) {
    const glm::dvec4 row = matrixRow(m, r);
    // P * V writes each row as a part along the view axis (V's forward row) and a part across it
    // (V's right and up rows); each entry is summed from those parts' terms.
    const double along = glm::dot(xyz(row), axis);
    const double across = glm::length(xyz(row) - along * axis);
    // The translation adds the parts times the eye's coordinates along and across the axis
    // (across bounded by Cauchy-Schwarz), and what the row leaves at the eye (the projection's
    // own translation: 0 for rows 0, 1 and 3, a |w| for the depth row).
    const double left = std::abs(glm::dot(row, glm::dvec4(anchor, 1.0)));
    const double translationTerms =
        std::abs(along * eyeAlong) + std::abs(across * eyeAcross) + left;
    for (int c = 0; c < 4; ++c) {
      const double terms = c < 3 ? std::abs(along * axis[c]) +
                                       across * std::sqrt(std::max(0.0, 1.0 - axis[c] * axis[c]))
                                 : translationTerms;
      const double arithmetic = perMagnitude * terms;
      // A decimal listing's rounding: uniform within half a unit in the last printed digit.
      const double decimal = decimalHalfUnit(row[c], precision.decimalDigits) / std::sqrt(3.0);
      // Double arithmetic stored as float32: the entry's own rounding to float32.
      const double stored = storedRounding * std::abs(row[c]);
      errors.deviation[c][r] =
          std::sqrt(arithmetic * arithmetic + decimal * decimal + stored * stored);
    }
  }
  // The depth row's coefficients are rounded before the product, and the depth row is often
  // formed from the w row (P22 z + P23 w in view space; Godot's and Filament's depth correction,
  // reversed-Z): an error of a multiple of the w row, common to its four entries. It cancels at
  // the eye (where w = 0) and moves only the depth the row tends to far away.
  errors.depthAlongW = perMagnitude;
  return errors;
}

MatrixReading readMatrix(const glm::dmat4& m, const EntryErrors& errors,
                         const glm::dvec3& orthographicAnchor) {
  const glm::dmat4& deviations = errors.deviation;
  MatrixReading reading;
  const glm::dvec3 wXyz = xyz(matrixRow(m, 3));
  const glm::dvec3 wErrors =
      kCoverage * glm::dvec3(deviations[0][3], deviations[1][3], deviations[2][3]);
  reading.perspective = glm::length(wXyz) > glm::length(wErrors) && glm::length(wXyz) > 0.0;
  reading.anchor = orthographicAnchor;
  const Figures base = figuresOf(m, reading.perspective, orthographicAnchor);

  // First-order propagation: each figure's variance is the sum over the entries of (its
  // derivative along the entry x the entry's standard deviation)^2. The derivatives are taken
  // through the whole reading (the eye, the view direction, the planes), so entries that enter a
  // figure along several paths (the translation through the eye and through the depth row) are
  // counted once, with their paths' effects added before squaring: that is the correlation.
  Figures spread;  // summed squared changes, then their root
  spread.a = spread.b = spread.nearNo = spread.nearZo = spread.atOne = 0.0;
  glm::dvec3 eyeSpread(0.0);
  double forwardSpread = 0.0;
  const auto add = [](double& sum, double changed, double scale) {
    const double c = changed * scale;
    sum += c * c;
  };
  // Each error mode: the matrix moved by one step along it, and the step's scale back to one
  // standard deviation.
  const auto propagate = [&](const glm::dmat4& moved, double scale) {
    const Figures f = figuresOf(moved, reading.perspective, orthographicAnchor);
    add(spread.a, change(f.a, base.a), scale);
    add(spread.b, change(f.b, base.b), scale);
    for (int k = 0; k < 3; ++k) add(eyeSpread[k], change(f.eye[k], base.eye[k]), scale);
    add(forwardSpread, angleBetween(f.forward, base.forward), scale);
    add(spread.nearNo, change(f.nearNo, base.nearNo), scale);
    add(spread.nearZo, change(f.nearZo, base.nearZo), scale);
    add(spread.atOne, change(f.atOne, base.atOne), scale);
    const auto angleChange = [](double angle, double baseAngle, const glm::dvec3& vector,
                                const glm::dvec3& baseVector) {
      return std::max(change(angle, baseAngle), glm::length(vector - baseVector));
    };
    add(spread.obliqueNo,
        angleChange(f.obliqueNo, base.obliqueNo, f.obliqueNoAcross, base.obliqueNoAcross), scale);
    add(spread.obliqueZo,
        angleChange(f.obliqueZo, base.obliqueZo, f.obliqueZoAcross, base.obliqueZoAcross), scale);
    add(spread.obliqueReversed,
        angleChange(f.obliqueReversed, base.obliqueReversed, f.obliqueReversedAcross,
                    base.obliqueReversedAcross),
        scale);
    add(spread.offAxis, angleChange(f.offAxis, base.offAxis, f.offAxisAcross, base.offAxisAcross),
        scale);
    add(spread.handedness, change(f.handedness, base.handedness), scale);
    add(spread.upY, change(f.upY, base.upY), scale);
    add(spread.fovY, change(f.fovY, base.fovY), scale);
    add(spread.fovX, change(f.fovX, base.fovX), scale);
    add(spread.extentX, change(f.extentX, base.extentX), scale);
    add(spread.extentY, change(f.extentY, base.extentY), scale);
  };
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      const double deviation = deviations[c][r];
      if (!(deviation > 0.0)) continue;
      // A step of one standard deviation, but never below double's resolution of the entry
      // (double listings), scaled back to one deviation.
      const double step = std::max(deviation, 1e-9 * std::abs(m[c][r]));
      glm::dmat4 moved = m;
      moved[c][r] += step;
      propagate(moved, deviation / step);
    }
  }
  if (errors.depthAlongW > 0.0) {
    const double step = std::max(errors.depthAlongW, 1e-9);
    glm::dmat4 moved = m;
    for (int c = 0; c < 4; ++c) moved[c][2] += step * m[c][3];
    propagate(moved, errors.depthAlongW / step);
  }
  const auto bound = [](double& sumOfSquares) {
    sumOfSquares = kCoverage * std::sqrt(sumOfSquares);
  };
  for (double* figure :
       {&spread.a, &spread.b, &spread.nearNo, &spread.nearZo, &spread.atOne, &spread.obliqueNo,
        &spread.obliqueZo, &spread.obliqueReversed, &spread.offAxis, &spread.handedness,
        &spread.upY, &spread.fovY, &spread.fovX, &spread.extentX, &spread.extentY, &forwardSpread,
        &eyeSpread.x, &eyeSpread.y, &eyeSpread.z})
    bound(*figure);
  // Each figure is itself computed in double from the entries: a few dozen roundings, relative
  // to its size (angles and unit-vector components: to 1).
  const double own = 32.0 * std::ldexp(1.0, -53);
  const auto relative = [&](double value) { return own * std::abs(value); };
  // a is the depth row at the eye: a cancellation of terms as large as the row times the eye's
  // distance, so its own rounding is relative to those terms (double entries far from the
  // origin), and moves every distance read from it in proportion.
  double ownA = relative(base.a);
  if (reading.perspective && std::isfinite(base.a) && base.a != 0.0) {
    const glm::dvec4 z = matrixRow(m, 2);
    const double terms = std::abs(z.w) + glm::length(xyz(z)) * glm::length(base.eye);
    ownA = std::max(ownA, 0.5 * own * terms / glm::length(wXyz));
  }
  spread.a += ownA;
  spread.b += relative(base.b) + own;
  const auto scaled = [&](double distance) {
    return reading.perspective && std::isfinite(distance) && std::isfinite(base.a) && base.a != 0.0
               ? std::abs(distance * ownA / base.a)
               : 0.0;
  };
  spread.nearNo += relative(base.nearNo) + scaled(base.nearNo);
  spread.nearZo += relative(base.nearZo) + scaled(base.nearZo);
  spread.atOne += relative(base.atOne) + scaled(base.atOne);
  for (double* angle : {&spread.obliqueNo, &spread.obliqueZo, &spread.obliqueReversed,
                        &spread.offAxis, &spread.handedness, &spread.upY})
    *angle += own;
  spread.fovY += relative(base.fovY);
  spread.fovX += relative(base.fovX);
  spread.extentX += relative(base.extentX);
  spread.extentY += relative(base.extentY);
  forwardSpread += own;
  for (int k = 0; k < 3; ++k) eyeSpread[k] += relative(base.eye[k]);
  reading.a = {base.a, spread.a};
  reading.b = {base.b, spread.b};
  reading.eye = base.eye;
  reading.eyeError = eyeSpread;
  reading.viewDirection = base.forward;
  reading.viewDirectionAngle = {0.0, forwardSpread};
  reading.nearIfNo = {base.nearNo, spread.nearNo};
  reading.nearIfZo = {base.nearZo, spread.nearZo};
  reading.nearIfReversed = {base.atOne, spread.atOne};
  reading.far = {base.atOne, spread.atOne};
  reading.farIfReversed = {base.nearZo, spread.nearZo};
  reading.obliqueAngleNo = {base.obliqueNo, spread.obliqueNo};
  reading.obliqueAngleZo = {base.obliqueZo, spread.obliqueZo};
  reading.obliqueAngleReversed = {base.obliqueReversed, spread.obliqueReversed};
  reading.offAxisAngle = {base.offAxis, spread.offAxis};
  reading.handedness = {base.handedness, spread.handedness};
  reading.screenUpY = {base.upY, spread.upY};
  reading.fovYDegrees = {base.fovY, spread.fovY};
  reading.fovXDegrees = {base.fovX, spread.fovX};
  reading.extentX = {base.extentX, spread.extentX};
  reading.extentY = {base.extentY, spread.extentY};
  return reading;
}

}  // namespace clipray
