#pragma once
// bench_rgbd_slam's rgbd_slam_steps/<preset>/WxH entry: every kernel of the pipeline timed on its own,
// and the heaviest ones against native C++ loops (see bench_rgbd_slam.cpp for the counters).

#include <benchmark/benchmark.h>

#include "bench_options.hpp"

namespace vifusion::bench {

void rgbdSlamSteps(benchmark::State& state, Size size);

}  // namespace vifusion::bench
