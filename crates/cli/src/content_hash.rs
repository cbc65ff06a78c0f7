//! A stable content hash for the names and keys of cached results (study references, device
//! probes): FNV-1a, 64 bits, the same on every run and every Rust version.

pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}
