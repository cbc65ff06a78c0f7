//! stratified sampler
