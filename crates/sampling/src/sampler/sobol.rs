//! sobol sampler
