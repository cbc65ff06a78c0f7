//! independent sampler
