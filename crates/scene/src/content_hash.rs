//! A stable content hash for the names and keys of cached results (study references, device
//! probes) and for telling scenes apart (render parts): FNV-1a, 64 bits, the same on every run,
//! machine and Rust version.

/// The 64-bit FNV-1a hash of `bytes`.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    fnv1a_extend(0xcbf2_9ce4_8422_2325, bytes)
}

/// [`fnv1a`] continued over more bytes (`fnv1a(a ++ b) == fnv1a_extend(fnv1a(a), b)`).
pub fn fnv1a_extend(hash: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(hash, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}
