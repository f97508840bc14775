#include <gtest/gtest.h>

#include <random>

#include "gpu_test_environment.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/reduction/row_reducer.hpp"

namespace vifusion {
namespace {

using test::GpuTest;

/// Rows shaped like ICP residuals: Jacobian entries of order 1 (normals, lever arms in metres),
/// residuals of a few millimetres, inverse-variance weights, ~10 % outliers with weight 0.
void fillRows(std::span<ResidualRow> rows, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> unit(0.0f, 1.0f);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (ResidualRow& row : rows) {
    for (float& j : row.J) j = unit(rng);
    row.r = 0.003f * unit(rng);
    row.w = uniform(rng) < 0.1f ? 0.0f : 1.0f / (0.002f + 0.01f * uniform(rng));
  }
}

struct Case {
  const char* name;
  ReductionVariant variant;
  ReductionLayout layout;
  uint32_t rows;
};

void PrintTo(const Case& c, std::ostream* out) { *out << c.name; }

class RowReducerTest : public GpuTest, public ::testing::WithParamInterface<Case> {};

TEST_P(RowReducerTest, MatchesTheDoublePrecisionCpuReference) {
  const Case c = GetParam();
  if (c.variant == ReductionVariant::Subgroup && !context().features().subgroup_arithmetic) {
    GTEST_SKIP() << "device has no subgroup arithmetic; the shared-memory variant covers it";
  }
  RowReducerOptions options;
  options.max_rows = c.rows;
  options.variant = c.variant;
  options.layout = c.layout;
  gpu::CapacityPlan plan;
  RowReducer reducer(context(), plan, options);
  const auto arena = gpu::MemoryArena::create(context(), plan);
  reducer.build(*arena);
  fillRows(reducer.rows(), 42 + c.rows);
  auto sequence = gpu::CommandSequence::create(context(), "reduce");
  sequence->record([&](gpu::CommandRecorder& recorder) { reducer.record(recorder, c.rows); });
  sequence->run();

  const NormalEquations6 gpu = reducer.result();
  const NormalEquations6 cpu = reduceRowsCpu(reducer.rows().first(c.rows));
  // fp32 partial sums of up to ~300 rows per invocation, then a 128-wide tree: relative error
  // stays near 1e-6; 1e-5 of the matrix norm leaves margin without hiding a wrong term.
  EXPECT_NEAR((gpu.H - cpu.H).norm() / cpu.H.norm(), 0.0, 1e-5);
  EXPECT_NEAR((gpu.b - cpu.b).norm() / cpu.b.norm(), 0.0, 1e-4);
  EXPECT_NEAR(gpu.weighted_squared_residual / cpu.weighted_squared_residual, 1.0, 1e-5);
  EXPECT_EQ(gpu.inliers, cpu.inliers);
  EXPECT_TRUE(gpu.H.isApprox(gpu.H.transpose()));
}

INSTANTIATE_TEST_SUITE_P(
    Variants, RowReducerTest,
    ::testing::Values(Case{"auto_640x480", ReductionVariant::Auto, ReductionLayout::Auto, 640 * 480},
                      Case{"subgroup_runs_640x480", ReductionVariant::Subgroup, ReductionLayout::ContiguousRuns, 640 * 480},
                      Case{"subgroup_stride_320x240", ReductionVariant::Subgroup, ReductionLayout::GridStride, 320 * 240},
                      Case{"shared_runs_640x480", ReductionVariant::SharedMemory, ReductionLayout::ContiguousRuns, 640 * 480},
                      Case{"shared_stride_320x240", ReductionVariant::SharedMemory, ReductionLayout::GridStride, 320 * 240},
                      // fewer rows than invocations: most invocations reduce nothing
                      Case{"shared_runs_1000_rows", ReductionVariant::SharedMemory, ReductionLayout::ContiguousRuns, 1000}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

TEST_F(GpuTest, RowReducerRejectsBadOptions) {
  RowReducerOptions options;
  options.workgroup_size = 16;
  gpu::CapacityPlan plan;
  EXPECT_THROW(RowReducer reducer(context(), plan, options), Error);
}

}  // namespace
}  // namespace vifusion
