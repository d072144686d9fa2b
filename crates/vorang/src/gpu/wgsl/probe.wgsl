// Entry points for the twin tests (gpu/twin.rs): each runs one shader function on a batch of
// inputs, `stride` numbers per invocation, and writes its results.

@group(0) @binding(0) var<storage, read> input: array<f64>;
@group(0) @binding(1) var<storage, read_write> output: array<f64>;
@group(0) @binding(2) var<storage, read> params: array<f64>;

fn exact_fma() -> bool {
    return params[0] != 0.0lf;
}

@compute @workgroup_size(64)
fn fma_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    // Every entry point binds all three buffers (the layout is derived from the uses).
    if (gid.x == 0u) {
        output[0] = select(fma(input[0], input[1], input[2]), -1.0lf, params[0] > 1.0lf);
    }
}

@compute @workgroup_size(64)
fn orient_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    _ = params[0];
    let i = gid.x;
    if (i >= arrayLength(&input) / 6u) {
        return;
    }
    let a = vec2<f64>(input[6u * i], input[6u * i + 1u]);
    let b = vec2<f64>(input[6u * i + 2u], input[6u * i + 3u]);
    let c = vec2<f64>(input[6u * i + 4u], input[6u * i + 5u]);
    output[2u * i] = f64(orient(a, b, c));
    output[2u * i + 1u] = select(0.0lf, 1.0lf, inside(a, b, c));
}

fn corner_at(at: u32) -> Corner {
    return Corner(vec2<f64>(input[at], input[at + 1u]), input[at + 2u], input[at + 3u], u32(input[at + 4u]));
}

@compute @workgroup_size(64)
fn face_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    _ = params[0];
    let i = gid.x;
    if (i >= arrayLength(&input) / 18u) {
        return;
    }
    let at = 18u * i;
    let p = vec2<f64>(input[at + 15u], input[at + 16u]);
    let r = face_hit(corner_at(at), corner_at(at + 5u), corner_at(at + 10u), p, input[at + 17u] != 0.0lf);
    output[2u * i] = r.x;
    output[2u * i + 1u] = r.y;
}

@compute @workgroup_size(64)
fn exit_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    _ = params[0];
    let i = gid.x;
    if (i >= arrayLength(&input) / 11u) {
        return;
    }
    let at = 11u * i;
    let s = array<vec2<f64>, 4>(
        vec2<f64>(input[at], input[at + 1u]),
        vec2<f64>(input[at + 2u], input[at + 3u]),
        vec2<f64>(input[at + 4u], input[at + 5u]),
        vec2<f64>(input[at + 6u], input[at + 7u]),
    );
    let p = vec2<f64>(input[at + 9u], input[at + 10u]);
    output[i] = f64(exit_face(s, i32(input[at + 8u]), p));
}

@compute @workgroup_size(64)
fn segment_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    _ = params[0];
    let i = gid.x;
    if (i >= arrayLength(&input) / 13u) {
        return;
    }
    let at = 13u * i;
    let far = vec3<f64>(input[at], input[at + 1u], input[at + 2u]);
    let near = vec3<f64>(input[at + 3u], input[at + 4u], input[at + 5u]);
    let mid = vec3<f64>(input[at + 6u], input[at + 7u], input[at + 8u]);
    let c = segment(far, near, mid, input[at + 9u] != 0.0lf, input[at + 10u], input[at + 11u], input[at + 12u]);
    output[4u * i] = c.b.x;
    output[4u * i + 1u] = c.b.y;
    output[4u * i + 2u] = c.b.z;
    output[4u * i + 3u] = c.theta;
}

@compute @workgroup_size(64)
fn pow_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    _ = params[0];
    let i = gid.x;
    if (i >= arrayLength(&input) / 2u) {
        return;
    }
    output[i] = pow_frac(input[2u * i], input[2u * i + 1u]);
}
