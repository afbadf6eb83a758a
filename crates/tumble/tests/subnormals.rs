//! The standard jointed scenes, the pyramid and the torus chain step without
//! arithmetic on subnormal numbers. An operation with a subnormal operand or
//! result costs a microcode assist of some 150 cycles on Intel cores, and
//! every one these scenes had was arithmetic the compiler began before the
//! branch that guards it, on bytes that hold no number: the fields of laws a
//! joint does not have, an empty `Option` (docs/pipeline.md, eighteenth
//! session; the heavy chain's step took half as long again on a Xeon).
//! Read from MXCSR's sticky flags on the stepping thread (one thread), so
//! x86-64 only; the compiler speculates in release builds, which is how
//! `make test` runs these tests.
#![cfg(target_arch = "x86_64")]

use tumble::scenes;

/// MXCSR's sticky flag for a subnormal operand.
const DENORMAL_OPERAND: u32 = 1 << 1;
/// MXCSR's sticky flag for a result too small for a normal number.
const UNDERFLOW: u32 = 1 << 4;

/// Clears MXCSR's six sticky exception flags on this thread.
#[allow(deprecated)] // `_mm_setcsr`: the one way to reach the flags from Rust
fn clear_flags() {
    use std::arch::x86_64::{_mm_getcsr, _mm_setcsr};
    // SAFETY: clearing the sticky flags changes no rounding and masks nothing.
    unsafe { _mm_setcsr(_mm_getcsr() & !0x3f) }
}

/// MXCSR's sticky exception flags on this thread.
#[allow(deprecated)]
fn flags() -> u32 {
    // SAFETY: a read of this thread's MXCSR.
    unsafe { std::arch::x86_64::_mm_getcsr() & 0x3f }
}

#[test]
fn jointed_scenes_the_pyramid_and_the_torus_chain_step_without_subnormal_arithmetic() {
    let cases = [
        (scenes::heavy_chain(), 600),
        (scenes::ragdoll_pile(), 40),
        (scenes::pyramid(), 600),
        (scenes::chain(), 100),
    ];
    for (mut scene, steps) in cases {
        scene.settings.threads = 1;
        let (mut world, _) = scene.build().unwrap();
        for step in 0..steps {
            clear_flags();
            world.step();
            let f = flags();
            assert!(
                f & (DENORMAL_OPERAND | UNDERFLOW) == 0,
                "{}: step {step} did arithmetic on subnormal numbers (MXCSR flags {f:#x}); \
                 `TRAP_SUBNORMALS=1` of examples/profile_stages, under gdb, names the operation",
                scene.name
            );
        }
    }
}
