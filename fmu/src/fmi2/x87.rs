//! The x87 control word that every FMI call computes with on 64-bit Windows.
//!
//! There the C runtime the DLL is linked with (MinGW-w64's) computes `exp`, `expm1`, `atan2`, `sincos`,
//! `asinh` … on the x87 unit, whose results depend on the precision set in the calling thread's x87
//! control word. The Windows x64 calling convention sets it to [`STANDARD`] (53-bit precision) at program
//! start, and the threads the FMU starts (the FMI 3.0 worker threads) run with that value, but a host may
//! run with another: a program built with MinGW-w64 runs with 64-bit precision (0x037F). On such a host the
//! contacts a worker evaluated would differ in their last bits from those the host's thread evaluated (the
//! results would depend on `threads`), and the results from those on other hosts. So each FMI call runs
//! with [`STANDARD`], and the host's control word is restored afterwards. Elsewhere nothing is done (on
//! Linux the C runtime computes the `double` functions with SSE, which the x87 control word does not
//! affect).

/// The standard x87 control word of the Windows x64 calling convention: every exception masked, 53-bit
/// precision, rounding to nearest.
pub const STANDARD: u16 = 0x027F;

/// Runs `f` with the x87 control word [`STANDARD`] on 64-bit Windows, then restores the caller's (also when
/// `f` panics).
pub fn standard<R>(f: impl FnOnce() -> R) -> R {
    #[cfg(all(windows, target_arch = "x86_64"))]
    {
        /// Restores the caller's control word when dropped.
        struct Restore(u16);
        impl Drop for Restore {
            fn drop(&mut self) {
                load(self.0);
            }
        }
        let _restore = Restore(stored());
        load(STANDARD);
        f()
    }
    #[cfg(not(all(windows, target_arch = "x86_64")))]
    f()
}

/// The x87 control word of this thread.
#[cfg(all(windows, target_arch = "x86_64"))]
fn stored() -> u16 {
    let mut word = 0u16;
    // SAFETY: fnstcw writes the two bytes of `word`; Rust's code does not use the x87 unit.
    unsafe {
        std::arch::asm!("fnstcw word ptr [{}]", in(reg) &mut word, options(nostack, preserves_flags));
    }
    word
}

/// Loads an x87 control word into this thread's x87 unit.
#[cfg(all(windows, target_arch = "x86_64"))]
fn load(word: u16) {
    // SAFETY: fldcw reads the two bytes of `word`; it changes only how the x87 unit rounds (Rust's code
    // does not use the x87 unit, and the C runtime's functions that do expect any control word).
    unsafe {
        std::arch::asm!("fldcw word ptr [{}]", in(reg) &word, options(nostack, preserves_flags, readonly));
    }
}
