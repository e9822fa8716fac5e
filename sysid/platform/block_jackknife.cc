#include "sysid/platform/block_jackknife.h"

#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace pwsim::sysid::platform {

JackknifeBound BlockJackknife(int blocks, const std::function<double(int excluded)>& statistic,
                              double level) {
  if (!(level > 0.5 && level < 1.0))
    throw std::invalid_argument("BlockJackknife: level must lie in (0.5, 1), got " +
                                std::to_string(level));
  JackknifeBound out;
  out.blocks = blocks;
  out.estimate = statistic(-1);
  if (blocks < 2) {
    out.se = std::numeric_limits<double>::infinity();
    out.lower = -std::numeric_limits<double>::infinity();
    return out;
  }
  std::vector<double> left_out(static_cast<std::size_t>(blocks));
  double mean = 0.0;
  for (int b = 0; b < blocks; ++b) {
    left_out[static_cast<std::size_t>(b)] = statistic(b);
    mean += left_out[static_cast<std::size_t>(b)];
  }
  mean /= blocks;
  double ss = 0.0;
  for (double v : left_out) ss += (v - mean) * (v - mean);
  const double b = static_cast<double>(blocks);
  out.se = std::sqrt((b - 1.0) / b * ss);
  const boost::math::students_t t(b - 1.0);
  out.lower = out.estimate - boost::math::quantile(t, level) * out.se;
  return out;
}

}  // namespace pwsim::sysid::platform
