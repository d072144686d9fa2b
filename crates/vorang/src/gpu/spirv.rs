//! The shaders as SPIR-V with every floating-point operation decorated `NoContraction`.
//!
//! Vulkan lets a driver rewrite float arithmetic that is not so marked: lavapipe's compiler
//! (NIR) turns `(a + b) − a` into `b` and factors `a·b + a·c`, which undoes the error-free
//! transformations of the exact predicates and the double-double depths, and other devices
//! fuse products into sums. WGSL has no way to say "as written", so the WGSL is translated
//! here (naga, the translator wgpu itself uses) and the decoration added to the result of every
//! float operation; the device then evaluates each one as IEEE 754 says, in the order written —
//! the order of the Rust twins.

/// Float operations (SPIR-V opcodes) whose results get `NoContraction`: OpFNegate, OpFAdd,
/// OpFSub, OpFMul, OpFDiv, OpFRem, OpFMod, OpVectorTimesScalar, OpMatrixTimesScalar,
/// OpVectorTimesMatrix, OpMatrixTimesVector, OpMatrixTimesMatrix, OpDot, and OpExtInst (the
/// GLSL.std.450 calls: fma, sqrt, floor, ceil, min, max, …).
const FLOAT_OPS: &[u32] = &[
    127, 129, 131, 133, 136, 140, 141, 142, 143, 144, 145, 146, 148, 12,
];

const OP_DECORATE: u32 = 71;
const NO_CONTRACTION: u32 = 42;

/// WGSL → SPIR-V words, the float operations marked.
pub fn compile(source: &str) -> Result<Vec<u32>, String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::FLOAT64,
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(source))?;
    let options = naga::back::spv::Options {
        lang_version: (1, 0),
        ..Default::default()
    };
    let words = naga::back::spv::write_vec(&module, &info, &options, None)
        .map_err(|e| format!("SPIR-V: {e}"))?;
    Ok(no_contraction(&words))
}

/// Adds `OpDecorate id NoContraction` for the result of every float operation, after the
/// module's other annotations (before its first type declaration).
pub fn no_contraction(words: &[u32]) -> Vec<u32> {
    const HEADER: usize = 5;
    let mut ids = Vec::new();
    let mut first_type = None;
    let mut at = HEADER;
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        let op = words[at] & 0xffff;
        if count == 0 {
            break;
        }
        // OpTypeVoid … OpTypeForwardPointer, constants, OpVariable: the declarations.
        if first_type.is_none() && ((19..=39).contains(&op) || (41..=52).contains(&op) || op == 59)
        {
            first_type = Some(at);
        }
        if FLOAT_OPS.contains(&op) && count >= 3 {
            ids.push(words[at + 2]);
        }
        at += count;
    }
    let insert = first_type.unwrap_or(words.len());
    let mut out = Vec::with_capacity(words.len() + 3 * ids.len());
    out.extend_from_slice(&words[..insert]);
    for id in ids {
        out.extend([(3 << 16) | OP_DECORATE, id, NO_CONTRACTION]);
    }
    out.extend_from_slice(&words[insert..]);
    out
}
