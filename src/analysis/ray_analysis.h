// Analysis of a shadow frame on the CPU (docs/methods/thesis.md "Accuracy", "The oracle"): where every candidate
// (pixel, light) pair went, the fewest rays any culler could trace, how accurate the reconstructed
// normals and world positions are, and a CPU shadow reference that repeats the GPU's decisions.
// Images are row-major, width × height, top row first; depth 0 = sky.
// One header per part: ray_accounting.h (and heatmaps), reference_surface.h, ray_oracle.h,
// reconstruction_accuracy.h, shadow_comparison.h.
#pragma once
#include "analysis/ray_accounting.h"
#include "analysis/ray_oracle.h"
#include "analysis/reconstruction_accuracy.h"
#include "analysis/reference_surface.h"
#include "analysis/shadow_comparison.h"
