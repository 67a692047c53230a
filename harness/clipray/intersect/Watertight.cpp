#include "clipray/intersect/Watertight.hpp"

#include <cmath>

namespace clipray {

void edgeFunctionsExtended(double ax, double ay, double bx, double by, double cx, double cy,
                           double& u, double& v, double& w) noexcept {
  const long double lu = static_cast<long double>(cx) * by - static_cast<long double>(cy) * bx;
  const long double lv = static_cast<long double>(ax) * cy - static_cast<long double>(ay) * cx;
  const long double lw = static_cast<long double>(bx) * ay - static_cast<long double>(by) * ax;
  u = static_cast<double>(lu);
  v = static_cast<double>(lv);
  w = static_cast<double>(lw);
}

}  // namespace clipray
