// Normal-equation accumulation for 6-parameter least squares, shared by every kernel that
// reduces residual rows (generic row reduction, ICP, photometric alignment).
//
// Each invocation sums its rows into NE_TERMS floats held in registers:
//   [0..20]  upper triangle of Jᵀ W J, row by row: (0,0) (0,1) .. (0,5) (1,1) .. (5,5)
//   [21..26] Jᵀ W r
//   [27]     Σ w r²
//   [28]     number of rows with w > 0 (inliers)
//   [29]     number of candidates: items with valid input, whether or not a gate accepted them
//            (the denominator of tracking-health ratios)
// The workgroup then reduces them to one partial of NE_STRIDE floats at partials[group * NE_STRIDE];
// the host sums the partials in double, so fp32 only ever adds one workgroup's share.
//
// The includer declares, before including this file:
//   layout(local_size_x_id = 0) in;                       (1-D workgroup, size ≥ NE_TERMS)
//   layout(std430, binding = N) writeonly buffer Partials { float partials[]; };
// defines VIFUSION_SUBGROUP_REDUCE to 1 (subgroup arithmetic) or 0 (shared memory only), and after
// including it defines neAddItem(acc, i), which accumulates item i (a row, a pixel); its main()
// then calls neReduceItems(count). Specialization constant 3 chooses how items are split.

#ifndef VIFUSION_REDUCE_NORMAL_EQUATIONS_GLSL
#define VIFUSION_REDUCE_NORMAL_EQUATIONS_GLSL

#define NE_TERMS 30
#define NE_STRIDE 32

// Every access to the accumulator uses a constant index, written out term by term (NE_FOR_EACH_TERM
// and neAccumulate) instead of loops over k: one loop whose index the compiler keeps dynamic makes
// the whole array indirectly addressed, and lavapipe (Mesa 22.3) then reads and writes it lane by
// lane through memory on every row. Measured at 640×480: ICP 25 → 12.5 CPU-ms per evaluation,
// photometric 26 → 12.7 ([[unroll]] hints alone did not help).
#define NE_FOR_EACH_TERM(X)                                                                              \
  X(0) X(1) X(2) X(3) X(4) X(5) X(6) X(7) X(8) X(9) X(10) X(11) X(12) X(13) X(14) X(15) X(16) X(17) X(18) \
  X(19) X(20) X(21) X(22) X(23) X(24) X(25) X(26) X(27) X(28) X(29)

#if VIFUSION_SUBGROUP_REDUCE
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif

void neClear(out float acc[NE_TERMS]) {
#define NE_CLEAR_TERM(k) acc[k] = 0.0;
  NE_FOR_EACH_TERM(NE_CLEAR_TERM)
#undef NE_CLEAR_TERM
}

void neCountCandidate(inout float acc[NE_TERMS]) { acc[29] += 1.0; }

void neAccumulate(inout float acc[NE_TERMS], float J[6], float r, float w) {
  if (!(w > 0.0)) return;
  // Row i of the upper triangle is w·J[i]·J[j] for j ≥ i, then w·J[i]·r (same products, same order
  // as the CPU reference's loops).
  const float wJ0 = w * J[0], wJ1 = w * J[1], wJ2 = w * J[2], wJ3 = w * J[3], wJ4 = w * J[4], wJ5 = w * J[5];
  acc[0] += wJ0 * J[0];
  acc[1] += wJ0 * J[1];
  acc[2] += wJ0 * J[2];
  acc[3] += wJ0 * J[3];
  acc[4] += wJ0 * J[4];
  acc[5] += wJ0 * J[5];
  acc[6] += wJ1 * J[1];
  acc[7] += wJ1 * J[2];
  acc[8] += wJ1 * J[3];
  acc[9] += wJ1 * J[4];
  acc[10] += wJ1 * J[5];
  acc[11] += wJ2 * J[2];
  acc[12] += wJ2 * J[3];
  acc[13] += wJ2 * J[4];
  acc[14] += wJ2 * J[5];
  acc[15] += wJ3 * J[3];
  acc[16] += wJ3 * J[4];
  acc[17] += wJ3 * J[5];
  acc[18] += wJ4 * J[4];
  acc[19] += wJ4 * J[5];
  acc[20] += wJ5 * J[5];
  acc[21] += wJ0 * r;
  acc[22] += wJ1 * r;
  acc[23] += wJ2 * r;
  acc[24] += wJ3 * r;
  acc[25] += wJ4 * r;
  acc[26] += wJ5 * r;
  acc[27] += w * r * r;
  acc[28] += 1.0;
}

#if VIFUSION_SUBGROUP_REDUCE
// One slot per subgroup; a workgroup has at most gl_WorkGroupSize.x subgroups (subgroup size 1).
shared float ne_subgroup_sums[gl_WorkGroupSize.x][NE_TERMS];

void neReduceAndStore(float acc[NE_TERMS]) {
#define NE_SUBGROUP_SUM(k)                                          \
  {                                                                 \
    const float sum = subgroupAdd(acc[k]);                          \
    if (subgroupElect()) ne_subgroup_sums[gl_SubgroupID][k] = sum;  \
  }
  NE_FOR_EACH_TERM(NE_SUBGROUP_SUM)
#undef NE_SUBGROUP_SUM
  barrier();
  // Invocation k adds term k across subgroups.
  const uint k = gl_LocalInvocationIndex;
  if (k < NE_TERMS) {
    float total = 0.0;
    for (uint s = 0; s < gl_NumSubgroups; ++s) total += ne_subgroup_sums[s][k];
    partials[gl_WorkGroupID.x * NE_STRIDE + k] = total;
  }
}
#else
// Tree reduction in shared memory; works for any workgroup size (odd tails are folded in).
shared float ne_invocation_sums[gl_WorkGroupSize.x][NE_TERMS];

void neReduceAndStore(float acc[NE_TERMS]) {
  const uint i = gl_LocalInvocationIndex;
#define NE_STORE_TERM(k) ne_invocation_sums[i][k] = acc[k];
  NE_FOR_EACH_TERM(NE_STORE_TERM)
#undef NE_STORE_TERM
  barrier();
  for (uint live = gl_WorkGroupSize.x; live > 1;) {
    const uint kept = (live + 1) / 2;
    if (i < live - kept) {
      for (int k = 0; k < NE_TERMS; ++k) ne_invocation_sums[i][k] += ne_invocation_sums[i + kept][k];
    }
    barrier();
    live = kept;
  }
  if (i < NE_TERMS) partials[gl_WorkGroupID.x * NE_STRIDE + i] = ne_invocation_sums[0][i];
}
#endif

// Contiguous runs suit CPU devices such as lavapipe (each invocation streams through memory); a
// grid stride coalesces loads on GPUs.
layout(constant_id = 3) const bool kContiguousRuns = true;

void neAddItem(inout float acc[NE_TERMS], int i);

// Accumulates this invocation's share of items 0..count−1 and stores the workgroup's partial.
void neReduceItems(int count) {
  float acc[NE_TERMS];
  neClear(acc);
  const int invocations = int(gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  const int id = int(gl_GlobalInvocationID.x);
  if (kContiguousRuns) {
    const int run = (count + invocations - 1) / invocations;
    const int last = min(id * run + run, count);
    for (int i = id * run; i < last; ++i) neAddItem(acc, i);
  } else {
    for (int i = id; i < count; i += invocations) neAddItem(acc, i);
  }
  neReduceAndStore(acc);
}

#endif  // VIFUSION_REDUCE_NORMAL_EQUATIONS_GLSL
