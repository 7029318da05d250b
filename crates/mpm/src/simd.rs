//! Kernels compiled twice: for the baseline target and with AVX2, chosen at run time.
//! Both versions do the same IEEE operations in the same order (Rust never contracts
//! a·b + c into an FMA on its own), so results are bitwise identical either way; AVX2
//! only buys the three-operand encodings and wider registers.

/// Wraps a kernel `fn name[generic declarations][generic arguments](args) -> ret {body}`
/// into a dispatcher that calls an AVX2-compiled copy of the body when the CPU has it.
macro_rules! multiversion {
    (
        $(#[$attr:meta])*
        $vis:vis fn $name:ident [$($decl:tt)*] [$($use:tt)*]
        ($($arg:ident : $argty:ty),* $(,)?) $(-> $ret:ty)? $body:block
    ) => {
        $(#[$attr])*
        #[inline(never)]
        // The one unsafe call in the workspace: the AVX2 copy runs only after the CPU
        // was seen to have AVX2.
        #[allow(unsafe_code)]
        $vis fn $name<$($decl)*>($($arg: $argty),*) $(-> $ret)? {
            #[inline(always)]
            fn body<$($decl)*>($($arg: $argty),*) $(-> $ret)? $body
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2")]
            unsafe fn avx2<$($decl)*>($($arg: $argty),*) $(-> $ret)? {
                body::<$($use)*>($($arg),*)
            }
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has AVX2, checked just above.
                return unsafe { avx2::<$($use)*>($($arg),*) };
            }
            body::<$($use)*>($($arg),*)
        }
    };
}

pub(crate) use multiversion;
