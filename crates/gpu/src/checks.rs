//! Which of wgpu's runtime checks the kernel is compiled with.
//!
//! wgpu adds code to every shader unless told otherwise (`wgpu::ShaderRuntimeChecks`): index
//! clamping, a counter in every loop, guards on every integer division. strata's kernel is its
//! own and tested, so a check that the kernel provably never needs can be left out
//! ([`KernelChecks::AUDITED`]: the fewest checks allowed without `unsafe`). The default,
//! [`KernelChecks::DEFAULT`], keeps one more than the audit needs, the loop counters, because an
//! NVIDIA H200 ran the kernel faster with them (measured:
//! docs/measurements/kernel-checks.md#on-an-nvidia-h200). The audit, check by check, is in
//! `docs/design/kernel-checks.md`; `--kernel-checks all` (and [`KernelChecks::ALL`]) compiles
//! the fully checked kernel, and the agreement tests render with the default and the fully
//! checked kernels.

/// The runtime checks the kernel is compiled with. [`KernelChecks::default`] is
/// [`KernelChecks::DEFAULT`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct KernelChecks {
    /// Clamp array indices, and buffer indices where the driver has no robust buffer access
    /// of its own.
    pub bounds: bool,
    /// Count every loop's iterations and leave the loop after 2⁶⁴ of them
    /// (`force_loop_bounding`): a shader compiler may otherwise treat an infinite loop as
    /// unreachable.
    pub loops: bool,
    /// Guard every integer division and remainder against a zero divisor and `i32::MIN / -1`.
    pub int_division: bool,
}

impl KernelChecks {
    /// Every check: wgpu's default, for any shader.
    pub const ALL: Self = Self {
        bounds: true,
        loops: true,
        int_division: true,
    };

    /// No check at all.
    pub const NONE: Self = Self {
        bounds: false,
        loops: false,
        int_division: false,
    };

    /// The checks the audit could not show the kernel never needs: the bounds checks. Every
    /// loop of the kernel is bounded by a constant or a validated count, and every integer
    /// divisor is a nonzero constant or a dimension the host checks
    /// (`docs/design/kernel-checks.md`).
    pub const AUDITED: Self = Self {
        bounds: true,
        loops: false,
        int_division: false,
    };

    /// The default: the audited checks and the loop counters. The audit shows the counters
    /// unneeded, but on an NVIDIA H200 (driver 580) the kernel without them ran slower on
    /// Veach's scene and on the mesh scene; on lavapipe they cost nothing measurable. The
    /// integer-division guards stay out: the audit shows them unneeded, and keeping them cost
    /// a little on the H200 (measured: docs/measurements/kernel-checks.md#on-an-nvidia-h200).
    pub const DEFAULT: Self = Self {
        bounds: true,
        loops: true,
        int_division: false,
    };

    /// The names of the checks, as `--kernel-checks` takes them.
    pub const NAMES: [&'static str; 3] = ["bounds", "loops", "int-division"];

    /// wgpu's settings for these checks. Ray-query and mesh-shader tracking stay on: the kernel
    /// uses neither, so they cost nothing.
    pub(crate) fn runtime_checks(self) -> wgpu::ShaderRuntimeChecks {
        let mut checks = wgpu::ShaderRuntimeChecks::checked();
        checks.bounds_checks = self.bounds;
        checks.force_loop_bounding = self.loops;
        checks.int_div_checks = self.int_division;
        checks
    }

    /// Whether every check `other` makes, these make too.
    pub fn covers(self, other: Self) -> bool {
        self.flags()
            .iter()
            .zip(other.flags())
            .all(|(mine, theirs)| *mine || !theirs)
    }

    fn flags(self) -> [bool; 3] {
        [self.bounds, self.loops, self.int_division]
    }

    /// The checks from a comma-separated list of [`KernelChecks::NAMES`], or `default`, `all`,
    /// `none` or `audited`.
    pub fn parse(list: &str) -> Result<Self, String> {
        match list.trim() {
            "default" => return Ok(Self::DEFAULT),
            "all" => return Ok(Self::ALL),
            "none" => return Ok(Self::NONE),
            "audited" => return Ok(Self::AUDITED),
            _ => {}
        }
        let mut flags = [false; 3];
        for name in list.split(',').map(str::trim) {
            let i = Self::NAMES.iter().position(|n| *n == name).ok_or_else(|| {
                format!(
                    "unknown check `{name}`: expected default, all, none, audited or a \
                     comma-separated list of {}",
                    Self::NAMES.join(", ")
                )
            })?;
            flags[i] = true;
        }
        Ok(Self {
            bounds: flags[0],
            loops: flags[1],
            int_division: flags[2],
        })
    }
}

impl Default for KernelChecks {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl std::fmt::Display for KernelChecks {
    /// The checks on, comma-separated (`none` for none), as [`KernelChecks::parse`] reads them.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let on: Vec<&str> = Self::NAMES
            .iter()
            .zip(self.flags())
            .filter_map(|(name, on)| on.then_some(*name))
            .collect();
        if on.is_empty() {
            f.write_str("none")
        } else {
            f.write_str(&on.join(","))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_set_of_checks_reads_back_from_its_name() {
        for bits in 0..8u8 {
            let checks = KernelChecks {
                bounds: bits & 1 != 0,
                loops: bits & 2 != 0,
                int_division: bits & 4 != 0,
            };
            assert_eq!(KernelChecks::parse(&checks.to_string()), Ok(checks));
        }
        assert_eq!(KernelChecks::parse("all"), Ok(KernelChecks::ALL));
        assert_eq!(KernelChecks::parse("audited"), Ok(KernelChecks::AUDITED));
        assert_eq!(KernelChecks::parse("default"), Ok(KernelChecks::default()));
        assert!(KernelChecks::ALL.covers(KernelChecks::DEFAULT));
        assert!(KernelChecks::DEFAULT.covers(KernelChecks::AUDITED));
        assert!(!KernelChecks::AUDITED.covers(KernelChecks::DEFAULT));
        assert!(!KernelChecks::NONE.covers(KernelChecks::AUDITED));
        assert!(KernelChecks::parse("bounds,speed")
            .unwrap_err()
            .contains("unknown check `speed`"));
    }

    #[test]
    fn wgpu_gets_exactly_the_checks_asked_for() {
        let checks = KernelChecks::AUDITED.runtime_checks();
        assert!(checks.bounds_checks && !checks.force_loop_bounding && !checks.int_div_checks);
        let default = KernelChecks::DEFAULT.runtime_checks();
        assert!(default.bounds_checks && default.force_loop_bounding && !default.int_div_checks);
        let all = KernelChecks::ALL.runtime_checks();
        assert!(all.bounds_checks && all.force_loop_bounding && all.int_div_checks);
    }
}
