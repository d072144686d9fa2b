// One invocation per pixel: the ray enters the mesh at each of the pixel's boundary entries (in
// depth order), marches cell to cell through the exit face that holds the pixel, integrates each
// cell's interval with the exact linear rule cut at the transfer function's knots, and
// composites front to back. Twin: gpu/twin.rs, pixel.

// Per cell: its nodes, then its neighbours across faces 0..3 (0xffffffff: none).
@group(0) @binding(0) var<storage, read> mesh: array<vec4<u32>>;
// Per node: screen x, y, depth (orthographic) or inverse depth (perspective), field value.
@group(0) @binding(1) var<storage, read> nodes: array<f64>;
// Per pixel p: its boundary entries (4·cell + face, nearest first) at lists[lists[p]] up to
// lists[lists[p + 1]] (the offsets count from the start of the buffer).
@group(0) @binding(2) var<storage, read> lists: array<u32>;
// Per pixel: the depth of the nearest grid line (only when consts[HAS_LINES] is 1).
@group(0) @binding(3) var<storage, read> lines: array<f64>;
// The frame's numbers and the transfer function (gpu/frame.rs, Consts).
@group(0) @binding(4) var<storage, read> consts: array<f64>;
// Per pixel: colour accumulated front to back (r, g, b) and transparency T.
@group(0) @binding(5) var<storage, read_write> image: array<f64>;

const WIDTH: u32 = 0u;
const HEIGHT: u32 = 1u;
const PERSPECTIVE: u32 = 2u;
const ENTRY_SIGN: u32 = 3u;
const FRONT_TO_BACK: u32 = 4u;
const DMIN: u32 = 5u;
const DMAX: u32 = 6u;
const TAN_X: u32 = 7u;
const TAN_Y: u32 = 8u;
const BRIGHTNESS: u32 = 9u;
const WEIGHTED: u32 = 10u;
const QUADRATIC: u32 = 11u;
const KNOTS: u32 = 12u;
const HAS_LINES: u32 = 13u;
const EXACT_FMA: u32 = 14u;
const CELLS: u32 = 15u;
const TABLE: u32 = 16u;
const NO_NEIGHBOR: u32 = 0xffffffffu;
// render::EARLY_TERMINATION for render_ftb; back to front nothing behind this shows.
const EARLY_TERMINATION: f64 = 1e-6lf;
const NEGLIGIBLE: f64 = 1e-20lf;

fn exact_fma() -> bool {
    return consts[EXACT_FMA] != 0.0lf;
}

fn knot_count() -> u32 {
    return u32(consts[KNOTS]);
}

fn knot(i: u32) -> f64 {
    return consts[TABLE + i];
}

// The piece of the table holding s: the number of knots ≤ s.
fn piece_of(s: f64) -> u32 {
    var n = 0u;
    for (var i = 0u; i < knot_count(); i++) {
        if (knot(i) <= s) {
            n++;
        }
    }
    return n;
}

// (η, χ) at s with the formula of piece p (Transfer1D::eval_in).
fn eval_in(p: u32, s: f64) -> vec4<f64> {
    let k = knot_count();
    let pieces = select(k + 1u, 1u, k == 0u);
    let at = TABLE + k + 9u * min(p, pieces - 1u);
    let d = s - consts[at];
    var r = vec4<f64>(
        consts[at + 1u] + d * consts[at + 5u],
        consts[at + 2u] + d * consts[at + 6u],
        consts[at + 3u] + d * consts[at + 7u],
        consts[at + 4u] + d * consts[at + 8u],
    );
    if (consts[WEIGHTED] != 0.0lf) {
        r = vec4<f64>(r.x * r.w, r.y * r.w, r.z * r.w, r.w);
    }
    return r;
}

// The pieces [u0, u1] of a cell's interval (u = 0 far, 1 near), with field values s_far and
// s_near at its ends and world length `length` (Exact::transfer_pixel's segment).
fn piece(u0: f64, u1: f64, p: u32, s_far: f64, s_near: f64, length: f64) -> Contribution {
    let s0 = s_far + u0 * (s_near - s_far);
    let s1 = s_far + u1 * (s_near - s_far);
    let mid = 0.5lf * (s0 + s1);
    let far = eval_in(p, s0);
    let near = eval_in(p, s1);
    let quadratic = consts[QUADRATIC] != 0.0lf;
    var eta_mid = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    if (quadratic) {
        eta_mid = eval_in(p, mid).xyz;
    }
    return segment(far.xyz, near.xyz, eta_mid, quadratic, far.w, near.w, (u1 - u0) * length);
}

fn accumulate(acc: Contribution, c: Contribution) -> Contribution {
    return Contribution(acc.b * c.theta + c.b, acc.theta * c.theta);
}

fn piece_between(u0: f64, u1: f64, s_far: f64, s_near: f64, length: f64) -> Contribution {
    let s0 = s_far + u0 * (s_near - s_far);
    let s1 = s_far + u1 * (s_near - s_far);
    return piece(u0, u1, piece_of(0.5lf * (s0 + s1)), s_far, s_near, length);
}

// A cell's (b, θ) for `exact linear 0` (Exact::transfer_pixel): cut where the field crosses a
// knot, each piece integrated exactly, far to near; b times the brightness.
fn cell_contribution(s_far: f64, s_near: f64, length: f64) -> Contribution {
    var acc = Contribution(vec3<f64>(0.0lf, 0.0lf, 0.0lf), 1.0lf);
    let p = piece_of(s_far);
    if (piece_of(s_near) == p) {
        acc = piece(0.0lf, 1.0lf, p, s_far, s_near, length);
    } else {
        let lo = min(s_far, s_near);
        let hi = max(s_far, s_near);
        let k = knot_count();
        var prev = 0.0lf;
        for (var j = 0u; j < k; j++) {
            // Knots strictly between the ends, in the order the ray meets them from the far end.
            let i = select(k - 1u - j, j, s_near > s_far);
            let x = knot(i);
            if (!(x > lo && x < hi)) {
                continue;
            }
            let u = (x - s_far) / (s_near - s_far);
            if (u > prev) {
                acc = accumulate(acc, piece_between(prev, u, s_far, s_near, length));
                prev = u;
            }
        }
        if (1.0lf > prev) {
            acc = accumulate(acc, piece_between(prev, 1.0lf, s_far, s_near, length));
        }
    }
    let k = consts[BRIGHTNESS];
    return Contribution(acc.b * k, acc.theta);
}

fn corner(n: u32, id: u32) -> Corner {
    return Corner(vec2<f64>(nodes[4u * n], nodes[4u * n + 1u]), nodes[4u * n + 2u], nodes[4u * n + 3u], id);
}

// (depth, field value) on face f of a cell with nodes `tet` at screen position p.
fn hit(tet: vec4<u32>, f: u32, p: vec2<f64>) -> vec2<f64> {
    let a = tet[face_node(f, 0u)];
    let b = tet[face_node(f, 1u)];
    let c = tet[face_node(f, 2u)];
    return face_hit(corner(a, a), corner(b, b), corner(c, c), p, consts[PERSPECTIVE] != 0.0lf);
}

fn screen_of(n: u32) -> vec2<f64> {
    return vec2<f64>(nodes[4u * n], nodes[4u * n + 1u]);
}

@compute @workgroup_size(8, 8)
fn march(@builtin(global_invocation_id) gid: vec3<u32>) {
    let width = u32(consts[WIDTH]);
    let height = u32(consts[HEIGHT]);
    if (gid.x >= width || gid.y >= height) {
        return;
    }
    let pix = gid.y * width + gid.x;
    let p = vec2<f64>(f64(gid.x) + 0.5lf, f64(gid.y) + 0.5lf);
    let ftb = consts[FRONT_TO_BACK] != 0.0lf;
    let stop = select(NEGLIGIBLE, EARLY_TERMINATION, ftb);
    let dmin = consts[DMIN];
    var dmax = consts[DMAX];
    if (consts[HAS_LINES] != 0.0lf) {
        dmax = min(dmax, lines[pix]);
    }
    var speed = 1.0lf;
    if (consts[PERSPECTIVE] != 0.0lf) {
        let xn = 2.0lf * p.x / consts[WIDTH] - 1.0lf;
        let yn = 1.0lf - 2.0lf * p.y / consts[HEIGHT];
        let dx = xn * consts[TAN_X];
        let dy = yn * consts[TAN_Y];
        speed = sqrt(dx * dx + dy * dy + 1.0lf);
    }
    let entry_sign = i32(consts[ENTRY_SIGN]);
    let cells = u32(consts[CELLS]);
    var color = vec3<f64>(0.0lf, 0.0lf, 0.0lf);
    var t = 1.0lf;
    var steps = 0u;
    let first = lists[pix];
    let last = lists[pix + 1u];
    for (var e = first; e < last; e++) {
        var cell = lists[e] >> 2u;
        var tet = mesh[2u * cell];
        let into = hit(tet, lists[e] & 3u, p);
        var d_in = into.x;
        var s_in = into.y;
        loop {
            if (t < stop || !(d_in < dmax) || steps > cells) {
                break;
            }
            steps++;
            let s = array<vec2<f64>, 4>(screen_of(tet.x), screen_of(tet.y), screen_of(tet.z), screen_of(tet.w));
            let x = exit_face(s, entry_sign, p);
            if (x > 3u) {
                break;
            }
            let out = hit(tet, x, p);
            // Rounding can put a face crossing ~1e-16 before the other one.
            let d_out = max(out.x, d_in);
            let s_out = out.y;
            let near = max(d_in, dmin);
            let far = min(d_out, dmax);
            if (near < far) {
                var s_near = s_in;
                var s_far = s_out;
                let span = d_out - d_in;
                if (near != d_in) {
                    s_near = s_in + (s_out - s_in) * ((near - d_in) / span);
                }
                if (far != d_out) {
                    s_far = s_in + (s_out - s_in) * ((far - d_in) / span);
                }
                let c = cell_contribution(s_far, s_near, (far - near) * speed);
                color = color + t * c.b;
                t = t * c.theta;
            }
            let next = mesh[2u * cell + 1u][x];
            if (next == NO_NEIGHBOR) {
                break;
            }
            cell = next;
            tet = mesh[2u * cell];
            d_in = out.x;
            s_in = s_out;
        }
    }
    image[4u * pix] = color.x;
    image[4u * pix + 1u] = color.y;
    image[4u * pix + 2u] = color.z;
    image[4u * pix + 3u] = t;
}
