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
//   [30]     Σ w e², e ≥ 0 a bound on the row's systematic error in r's units (neAccumulateBounded;
//            0 for rows offered by neAccumulate)
// The workgroup then reduces them to one partial of NE_STRIDE floats at partials[group * NE_STRIDE];
// the host sums the partials in double, so fp32 only ever adds one workgroup's share.
//
// The includer declares, before including this file:
//   layout(local_size_x_id = 0) in;                       (1-D workgroup, size ≥ NE_TERMS)
//   layout(std430, binding = N) writeonly buffer Partials { float partials[]; };
// defines VIFUSION_SUBGROUP_REDUCE to 1 (subgroup arithmetic) or 0 (shared memory only), and after
// including it defines neAddItem(acc, i), which offers item i (a row, a pixel): neCountCandidate(acc)
// when its input is valid, then at most one neAccumulate(acc, J, r, w) or neAccumulateBounded(acc, J,
// r, w, e); its main() then calls
// neReduceItems(count). Specialization constant 3 chooses how items are split.

#ifndef VIFUSION_REDUCE_NORMAL_EQUATIONS_GLSL
#define VIFUSION_REDUCE_NORMAL_EQUATIONS_GLSL

#define NE_TERMS 31
#define NE_STRIDE 32

// Every access to the accumulator uses a constant index, written out term by term (NE_FOR_EACH_TERM
// and neAccumulate) instead of loops over k: one loop whose index the compiler keeps dynamic makes
// the whole array indirectly addressed, and lavapipe (Mesa 22.3) then reads and writes it lane by
// lane through memory on every row. Measured at 640×480: ICP 25 → 12.5 CPU-ms per evaluation,
// photometric 26 → 12.7 ([[unroll]] hints alone did not help).
#define NE_FOR_EACH_TERM(X)                                                                              \
  X(0) X(1) X(2) X(3) X(4) X(5) X(6) X(7) X(8) X(9) X(10) X(11) X(12) X(13) X(14) X(15) X(16) X(17) X(18) \
  X(19) X(20) X(21) X(22) X(23) X(24) X(25) X(26) X(27) X(28) X(29) X(30)

#if VIFUSION_SUBGROUP_REDUCE
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif

void neClear(out float acc[NE_TERMS]) {
#define NE_CLEAR_TERM(k) acc[k] = 0.0;
  NE_FOR_EACH_TERM(NE_CLEAR_TERM)
#undef NE_CLEAR_TERM
}

// The row the current item offers, held from neAccumulate until neAddItem has returned; all zero
// when it offers none. neAddItem's gates are nested branches, and lavapipe runs branches as masked
// code for all lanes with a select per modified value at every join: updating every sum at the
// deepest level costs one select per sum, nesting level and item; holding the row (J, r, w, e) there
// and adding it once per item at the top of the loop costs one per held value (tests/bench/README.md
// has the measured gain). A skipped row adds exact zeros, so the sums
// are unchanged, up to the sign of a zero sum. Each item offers at most one row.
float ne_row_J0, ne_row_J1, ne_row_J2, ne_row_J3, ne_row_J4, ne_row_J5, ne_row_r, ne_row_w, ne_row_e;
float ne_row_candidate;

void neCountCandidate(inout float acc[NE_TERMS]) { ne_row_candidate = 1.0; }

void neAccumulateBounded(inout float acc[NE_TERMS], float J[6], float r, float w, float e) {
  if (!(w > 0.0)) return;
  ne_row_J0 = J[0];
  ne_row_J1 = J[1];
  ne_row_J2 = J[2];
  ne_row_J3 = J[3];
  ne_row_J4 = J[4];
  ne_row_J5 = J[5];
  ne_row_r = r;
  ne_row_w = w;
  ne_row_e = e;
}

void neAccumulate(inout float acc[NE_TERMS], float J[6], float r, float w) { neAccumulateBounded(acc, J, r, w, 0.0); }

void neClearRow() {
  ne_row_J0 = 0.0;
  ne_row_J1 = 0.0;
  ne_row_J2 = 0.0;
  ne_row_J3 = 0.0;
  ne_row_J4 = 0.0;
  ne_row_J5 = 0.0;
  ne_row_r = 0.0;
  ne_row_w = 0.0;
  ne_row_e = 0.0;
  ne_row_candidate = 0.0;
}

// Adds the held row: w·JᵀJ (upper triangle row by row), w·J·r, w·r², the inlier, the candidate and w·e².
void neAddRow(inout float acc[NE_TERMS]) {
  const float w = ne_row_w, r = ne_row_r;
  const float J0 = ne_row_J0, J1 = ne_row_J1, J2 = ne_row_J2, J3 = ne_row_J3, J4 = ne_row_J4, J5 = ne_row_J5;
  // Row i of the upper triangle is w·J[i]·J[j] for j ≥ i, then w·J[i]·r (same products, same order
  // as the CPU reference's loops).
  const float wJ0 = w * J0, wJ1 = w * J1, wJ2 = w * J2, wJ3 = w * J3, wJ4 = w * J4, wJ5 = w * J5;
  acc[0] += wJ0 * J0;
  acc[1] += wJ0 * J1;
  acc[2] += wJ0 * J2;
  acc[3] += wJ0 * J3;
  acc[4] += wJ0 * J4;
  acc[5] += wJ0 * J5;
  acc[6] += wJ1 * J1;
  acc[7] += wJ1 * J2;
  acc[8] += wJ1 * J3;
  acc[9] += wJ1 * J4;
  acc[10] += wJ1 * J5;
  acc[11] += wJ2 * J2;
  acc[12] += wJ2 * J3;
  acc[13] += wJ2 * J4;
  acc[14] += wJ2 * J5;
  acc[15] += wJ3 * J3;
  acc[16] += wJ3 * J4;
  acc[17] += wJ3 * J5;
  acc[18] += wJ4 * J4;
  acc[19] += wJ4 * J5;
  acc[20] += wJ5 * J5;
  acc[21] += wJ0 * r;
  acc[22] += wJ1 * r;
  acc[23] += wJ2 * r;
  acc[24] += wJ3 * r;
  acc[25] += wJ4 * r;
  acc[26] += wJ5 * r;
  acc[27] += w * r * r;
  acc[28] += w > 0.0 ? 1.0 : 0.0;
  acc[29] += ne_row_candidate;
  acc[30] += w * ne_row_e * ne_row_e;
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
    for (int i = id * run; i < last; ++i) {
      neClearRow();
      neAddItem(acc, i);
      neAddRow(acc);
    }
  } else {
    for (int i = id; i < count; i += invocations) {
      neClearRow();
      neAddItem(acc, i);
      neAddRow(acc);
    }
  }
  neReduceAndStore(acc);
}

#endif  // VIFUSION_REDUCE_NORMAL_EQUATIONS_GLSL
