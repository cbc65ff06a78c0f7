//! Integer hashes shared by the samplers (mirrored in WGSL: only u32 wrapping arithmetic,
//! shifts, xor and reverse_bits).
