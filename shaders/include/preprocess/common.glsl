// Conventions shared by the preprocessing kernels (shaders/*.comp); the C++ references in
// pipeline/preprocess/src mirror every function here.
#ifndef VIFUSION_PREPROCESS_COMMON_GLSL
#define VIFUSION_PREPROCESS_COMMON_GLSL

// Metric depth stores 0 for "no measurement". Testing "> 0" rather than "!= 0" also rejects
// negative values and NaN, which no stage produces but a corrupt buffer could hold.
bool isValidDepth(float depth_m) { return depth_m > 0.0; }

// Vertex maps store vec4(0) for "no vertex". Every real vertex lies in front of the camera, so
// z > 0 decides validity without relying on w (later stages may reuse w for e.g. confidence).
bool isValidVertex(vec4 vertex_m) { return vertex_m.z > 0.0; }

// Images are row-major and tightly packed.
int pixelIndex(ivec2 pixel, int width) { return pixel.y * width + pixel.x; }

// Separable 5-tap Gaussian of the image pyramids (binomial 1 4 6 4 1 / 16). Every weight and every
// product of two weights is exact in float, and the weights sum to exactly 1.
const float kPyramidWeights[5] = float[5](0.0625, 0.25, 0.375, 0.25, 0.0625);

#endif
