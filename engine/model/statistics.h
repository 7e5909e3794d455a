// Order statistics of a sample, said once (the bench's frame times, the convergence study's
// errors).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace aeroflock {

// The p-th quantile (0..1), linear between the order statistics; 0 for no values.
inline double quantile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double x = p * double(v.size() - 1);
  const size_t i = size_t(std::floor(x));
  const size_t j = std::min(i + 1, v.size() - 1);
  return v[i] + (x - double(i)) * (v[j] - v[i]);
}

// The median: for an even count, halfway between the middle two.
inline double median(std::vector<double> v) { return quantile(std::move(v), 0.5); }

}  // namespace aeroflock
