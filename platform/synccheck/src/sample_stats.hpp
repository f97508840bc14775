#pragma once
// Order and moment statistics of a sample, NaN when the sample is too small to have them.

#include <span>
#include <vector>

namespace vifusion::synccheck {

/// The middle value (the mean of the two middle ones for an even count); NaN when empty.
double median(std::vector<double> values);
/// The `fraction` quantile, linearly interpolated between order statistics (Hyndman–Fan type 7, what
/// numpy.percentile does); fraction in [0, 1]. NaN when empty.
double quantile(std::vector<double> values, double fraction);
double mean(std::span<const double> values);  ///< NaN when empty
/// Sample standard deviation (n − 1); NaN below two values.
double sampleStd(std::span<const double> values);
double maxAbs(std::span<const double> values);  ///< NaN when empty

}  // namespace vifusion::synccheck
