// Photon noise (docs/method.md §3, the paper's Algorithm 1) and its random
// streams, in three parts: noise_stream.h (seeds, streams, lanes, Box-Muller
// normals), poisson_sampler.h (the Poisson variates of one elementary
// exposure, row by row) and aggregated_sampler.h (the numerical mode's frames
// aggregated, docs/method.md §6c).
#pragma once

#include "model/aggregated_sampler.h"
#include "model/noise_stream.h"
#include "model/poisson_sampler.h"
