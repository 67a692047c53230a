#pragma once
// What a world-to-clip matrix says about its camera, each figure with the uncertainty the matrix's
// entries carry. clipFromWorld is column-major, p_clip = clipFromWorld * p_world, in GL clip space
// (x, y in [-w, w]; z in [z_n w, w] with z_n = -1 for NO, 0 for ZO), for either convention: both
// readings of the near plane are given, since the matrix alone cannot say which was meant.
//
// Apps upload float32 matrices, often printed as decimals; a property decided with a fixed
// threshold is then decided by rounding noise. Here every decision compares a figure with its own
// uncertainty, propagated to first order from an error model of the entries (EntryPrecision,
// entryErrors): a matrix built in arithmetic of unit roundoff u carries, per entry, a few
// roundings at the size of the terms it was summed from, and a decimal listing adds up to half a
// unit in its last printed digit (docs/check.md, "Uncertainty").

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace clipray {

// The arithmetic a matrix's entries come from, and how they were written down.
struct EntryPrecision {
  enum class Arithmetic { Float32, Double };
  Arithmetic arithmetic = Arithmetic::Double;
  // Significant decimal digits of a decimal listing that is not exact in binary (0: exact binary,
  // or decimals that round-trip the binary values, such as float32 printed with %.9g).
  int decimalDigits = 0;
  // The values are float32 (exactly, or as round-tripping decimals): with double arithmetic
  // (--precision double: three.js, Filament), each entry carries that one rounding as well.
  bool storedAsFloat32 = false;
  double unitRoundoff() const;      // 2^-24 or 2^-53
  double decimalRelative() const;   // half a unit in the last printed digit, or 0
  std::string description() const;  // "float32", "float32 as 6-digit decimals", "double", ...
};

// Detects the precision from the values: all exactly float32 (as uploaded), all within the 9-digit
// rounding of a float32 (printed with %.9g: round-trips), decimals of at most d significant
// digits (printed with %g, %.4f...: treated as float32 arithmetic, the common case), or double.
EntryPrecision detectEntryPrecision(const std::vector<glm::dmat4>& matrices);

// A figure and the bound on its error from the entries' precision: 4.5 standard deviations of the
// error that the entries' rounding propagates to it (first order, the entries' roundings
// independent, each entry's effect followed through every path it takes).
struct Uncertain {
  double value = 0.0;
  double error = 0.0;
  // The figure is known to be non-zero, positive, ...: it clears its own error.
  bool clearlyPositive() const { return value > error; }
  bool clearlyNegative() const { return value < -error; }
  bool withinErrorOfZero() const { return !(std::abs(value) > error); }
};

// The errors a matrix's entries carry under a precision, as standard deviations. A matrix computed
// as P * V carries, per entry, a few roundings at the magnitude of the terms it was summed from:
// each row is a part along the view axis (V's forward row) and a part across it (V's right and up
// rows), so an xyz entry's terms are the part along times the axis's component plus the part
// across times the rest (bounded by Cauchy-Schwarz), and the translation's the parts times the
// eye's distances along and across the axis, plus what the row leaves at the eye (the depth row's
// own translation); `anchor` is the eye. A decimal listing adds its own rounding, uniform within
// half a unit in the last digit. These are independent; the depth row also carries a common
// error: a multiple of the w row (its coefficients rounded, depth rows formed from w).
struct EntryErrors {
  glm::dmat4 deviation{0.0};  // per entry, independent
  double depthAlongW = 0.0;   // the depth row moved by this multiple of the w row
};
EntryErrors entryErrors(const glm::dmat4& clipFromWorld, const EntryPrecision& precision,
                        const glm::dvec3& anchor);

// Half a unit in the last of `digits` significant digits of value as printed (0 for digits 0).
double decimalHalfUnit(double value, int digits);

// The number with at most two significant digits nearest to v (what apps type: 0.1, 0.05, 0.25,
// 1000): a near plane is read as typed when its reading lies within its uncertainty of one.
double nearestRoundNumber(double v);

struct MatrixReading {
  bool perspective = true;  // decided: |row 3 xyz| clears its error
  // Perspective: along the view direction at distance s from the eye, z_ndc(s) = b + a / s.
  Uncertain a, b;
  glm::dvec3 eye{0.0}, eyeError{0.0};
  glm::dvec3 viewDirection{0.0};  // forward: w grows along it (perspective); depth grows (ortho)
  Uncertain viewDirectionAngle;   // radians: value 0, error the direction's angular uncertainty
  // Near plane if built for NO (z_ndc = -1), for ZO (z_ndc = 0), if reversed (z_ndc = 1), and
  // the far plane (z_ndc = 1, or 0 reversed): distances from the eye; NaN where the reading has
  // no positive distance. Orthographic: signed offsets along the view direction from the anchor.
  Uncertain nearIfNo, nearIfZo, nearIfReversed, far, farIfReversed;
  // Angles in radians between the near plane's normal and the view direction (under NO's and
  // ZO's near plane), and between the image centre's ray and the view direction.
  Uncertain obliqueAngleNo, obliqueAngleZo, obliqueAngleReversed, offAxisAngle;
  // (screen right x screen up) . forward for unit vectors: negative for GL's right-handed camera.
  Uncertain handedness;
  Uncertain screenUpY;  // world y of the unit screen-up vector
  Uncertain fovYDegrees, fovXDegrees;
  // Orthographic: the view volume's width and height, and the anchor offsets are measured from.
  Uncertain extentX, extentY;
  glm::dvec3 anchor{0.0};
};

// Reads clipFromWorld with its entries' errors (entryErrors); anchor (orthographic only) is the
// point near and far offsets are measured from: the camera position when a view matrix is known,
// else the world origin (which is the camera's position when the matrix is a projection alone).
MatrixReading readMatrix(const glm::dmat4& clipFromWorld, const EntryErrors& errors,
                         const glm::dvec3& orthographicAnchor);

// The eye of a perspective matrix (the null vector of rows 0, 1, 3), or the centre of an
// orthographic view volume's NDC origin: where the translation column's terms are anchored.
glm::dvec3 translationAnchor(const glm::dmat4& clipFromWorld);

// The value with as many significant digits as its uncertainty allows (1 to 6): a float32
// reading of 0.0999999 +- 1.5e-5 shows as 0.1.
std::string shownReading(const Uncertain& reading);

// Significant decimal digits needed to write v to within relativeTolerance of it (1..17; 18: not
// at all). A plane an app typed (0.1, 0.05, 1000) needs one or two; a derived one needs many.
int significantDigits(double v, double relativeTolerance);

}  // namespace clipray
