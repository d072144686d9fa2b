// One invocation per pixel: the ray enters the mesh at each of the pixel's boundary entries (in
// depth order), marches cell to cell through the exit face that holds the pixel, integrates each
// cell's interval with the exact linear rule cut at the transfer function's knots, and
// composites front to back. Twin: gpu/twin.rs, pixel.

// Per cell: its nodes, then its neighbours across faces 0..3 (0xffffffff: none); a mesh larger
// than one binding holds continues in mesh1, mesh2, mesh3 (consts[PART_ROWS] rows each).
@group(0) @binding(0) var<storage, read> mesh: array<vec4<u32>>;
@group(0) @binding(6) var<storage, read> mesh1: array<vec4<u32>>;
@group(0) @binding(7) var<storage, read> mesh2: array<vec4<u32>>;
@group(0) @binding(8) var<storage, read> mesh3: array<vec4<u32>>;
// Per node (consts[NODE] numbers): screen x, y, depth (orthographic) or inverse depth
// (perspective), eye-space x, y, z, then the field value (exact) or η (r, g, b) and χ mapped at
// the node (interpolateCoeff).
@group(0) @binding(1) var<storage, read> nodes: array<f64>;
// Per pixel p: its boundary entries (4·cell + face, nearest first) at lists[lists[p]] up to
// lists[lists[p + 1]] (the offsets count from the start of the buffer); for interpolateColor
// one word per cell follows, its fan (color.wgsl).
@group(0) @binding(2) var<storage, read> lists: array<u32>;
// Per pixel: the depth of the nearest grid line (only when consts[HAS_LINES] is 1).
@group(0) @binding(3) var<storage, read> lines: array<f64>;
// The frame's numbers and the transfer function (gpu/frame.rs, Consts).
@group(0) @binding(4) var<storage, read> consts: array<f64>;
// Per pixel: colour accumulated front to back (r, g, b), transparency T, and the number of cells
// the ray passed (the frame's ray segments).
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
const NODE: u32 = 16u;
const METHOD: u32 = 17u;
// The rays' origin and direction as affine functions of the screen position
// (scene::RayPlanes): origin[r][k] at PLANES + 3r + k, direction at PLANES + 9 + 3r + k.
const PLANES: u32 = 18u;
// scene::RayPlanes::max_speed, and +∞ (WGSL has no literal for it).
const MAX_SPEED: u32 = 36u;
const INFINITY: u32 = 37u;
// The rows of the mesh in each of its bindings.
const PART_ROWS: u32 = 38u;
// 1 where some cell reaches in front of the perspective near plane.
const ANY_NEAR: u32 = 39u;
// interpolateColor: where the cells' fan codes start in `lists` (color.wgsl).
const FANS: u32 = 40u;
// 2: the iterations of the loop that checks the driver ran every loop to its end (loops_ran).
const LOOP_CHECK: u32 = 41u;
const TABLE: u32 = 42u;
// A pixel's entry into a cell that reaches in front of the perspective near plane: the cell
// number with this bit set (else 4·cell + face of a boundary face).
const NEAR_ENTRY: u32 = 0x80000000u;
// render::cell's PARALLEL.
const PARALLEL: f64 = 1e-12lf;
const METHOD_EXACT: f64 = 0.0lf;
const METHOD_COLOR: f64 = 2.0lf;
const F64_MAX: f64 = 1.7976931348623157e308lf;
const NO_NEIGHBOR: u32 = 0xffffffffu;
// render::EARLY_TERMINATION for render_ftb; back to front nothing behind this shows.
const EARLY_TERMINATION: f64 = 1e-6lf;
const NEGLIGIBLE: f64 = 1e-20lf;

// Row i of the mesh (2·cell: its nodes, 2·cell + 1: its neighbours), in whichever binding holds
// it.
fn mesh_at(i: u32) -> vec4<u32> {
    let rows = u32(consts[PART_ROWS]);
    let part = i / rows;
    let j = i - part * rows;
    switch part {
        case 0u: {
            return mesh[j];
        }
        case 1u: {
            return mesh1[j];
        }
        case 2u: {
            return mesh2[j];
        }
        default: {
            return mesh3[j];
        }
    }
}

fn exact_fma() -> bool {
    return consts[EXACT_FMA] != 0.0lf;
}

fn knot_count() -> u32 {
    return u32(consts[KNOTS]);
}

fn knot(i: u32) -> f64 {
    return consts[TABLE + i];
}

// The piece of the table holding s: the number of knots ≤ s (Transfer1D::piece), by bisection
// of the increasing knots. A count over every knot would cost each lookup as many loop
// iterations as the table has knots, and lavapipe ends the loops of a batch of invocations
// that run too many of them all together (docs/gpu.md).
fn piece_of(s: f64) -> u32 {
    var lo = 0u;
    var hi = knot_count();
    while (lo < hi) {
        let mid = lo + (hi - lo) / 2u;
        if (knot(mid) <= s) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// The number of knots < s, by bisection.
fn knots_below(s: f64) -> u32 {
    var lo = 0u;
    var hi = knot_count();
    while (lo < hi) {
        let mid = lo + (hi - lo) / 2u;
        if (knot(mid) < s) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return lo;
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
// knot, each piece integrated exactly, far to near; b times the brightness. Only the knots
// strictly between the ends are visited (Transfer1D::knots_between: first .. last).
fn cell_contribution(s_far: f64, s_near: f64, length: f64) -> Contribution {
    var acc = Contribution(vec3<f64>(0.0lf, 0.0lf, 0.0lf), 1.0lf);
    let p = piece_of(s_far);
    if (piece_of(s_near) == p) {
        acc = piece(0.0lf, 1.0lf, p, s_far, s_near, length);
    } else {
        let rising = s_near > s_far;
        let lo = select(s_near, s_far, rising);
        let hi = select(s_far, s_near, rising);
        let first = piece_of(lo);
        let last = max(knots_below(hi), first);
        var prev = 0.0lf;
        for (var j = 0u; j < last - first; j++) {
            // In the order the ray meets them from the far end.
            let i = select(last - 1u - j, first + j, rising);
            let u = (knot(i) - s_far) / (s_near - s_far);
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

fn node_at(n: u32) -> u32 {
    return u32(consts[NODE]) * n;
}

fn corner(n: u32, id: u32) -> Corner {
    let i = node_at(n);
    return Corner(vec2<f64>(nodes[i], nodes[i + 1u]), nodes[i + 2u], nodes[i + 6u], id);
}

// (depth, field value) on face f of a cell with nodes `tet` at screen position p.
fn hit(tet: vec4<u32>, f: u32, p: vec2<f64>) -> vec2<f64> {
    let a = tet[face_node(f, 0u)];
    let b = tet[face_node(f, 1u)];
    let c = tet[face_node(f, 2u)];
    return face_hit(corner(a, a), corner(b, b), corner(c, c), p, consts[PERSPECTIVE] != 0.0lf);
}

fn screen_of(n: u32) -> vec2<f64> {
    let i = node_at(n);
    return vec2<f64>(nodes[i], nodes[i + 1u]);
}

fn eye_of(n: u32) -> vec3<f64> {
    let i = node_at(n);
    return vec3<f64>(nodes[i + 3u], nodes[i + 4u], nodes[i + 5u]);
}

fn dot3(a: vec3<f64>, b: vec3<f64>) -> f64 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

fn cross3(a: vec3<f64>, b: vec3<f64>) -> vec3<f64> {
    return vec3<f64>(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

// The barycentric coordinates λ(τ) = a + τ·b of a cell along the ray of pixel p, τ the depth.
struct Line {
    a: vec4<f64>,
    b: vec4<f64>,
    // CellRays' tolerance for rays parallel to a face plane (only where asked for).
    tol: vec4<f64>,
    proper: bool,
}

fn plane(at: u32, g: vec3<f64>, k: u32) -> f64 {
    return g.x * consts[at + k] + g.y * consts[at + 3u + k] + g.z * consts[at + 6u + k];
}

// render::cell's EyeCell::new (mesh::barycentric_gradients), CellRays::new and CellRays::line,
// operation for operation: the CPU's per-ray path takes the field from these, so the GPU takes
// it from the same bits. Not proper for a flat cell, which the CPU does not draw.
fn cell_line(tet: vec4<u32>, p: vec2<f64>, with_tol: bool) -> Line {
    let c = array<vec3<f64>, 4>(eye_of(tet.x), eye_of(tet.y), eye_of(tet.z), eye_of(tet.w));
    let e1 = c[1] - c[0];
    let e2 = c[2] - c[0];
    let e3 = c[3] - c[0];
    let det = dot3(cross3(e1, e2), e3);
    var line = Line(vec4<f64>(0.0lf), vec4<f64>(0.0lf), vec4<f64>(0.0lf), false);
    if (!(det != 0.0lf && abs(det) <= F64_MAX)) {
        return line;
    }
    let g1 = cross3(e2, e3) / det;
    let g2 = cross3(e3, e1) / det;
    let g3 = cross3(e1, e2) / det;
    let g = array<vec3<f64>, 4>(-(g1 + g2 + g3), g1, g2, g3);
    for (var i = 0u; i < 4u; i++) {
        let h = 1.0lf - dot3(g[i], c[i]);
        let a0 = plane(PLANES, g[i], 0u) + h;
        let a1 = plane(PLANES, g[i], 1u);
        let a2 = plane(PLANES, g[i], 2u);
        let b0 = plane(PLANES + 9u, g[i], 0u);
        let b1 = plane(PLANES + 9u, g[i], 1u);
        let b2 = plane(PLANES + 9u, g[i], 2u);
        line.a[i] = a0 + a1 * p.x + a2 * p.y;
        line.b[i] = b0 + b1 * p.x + b2 * p.y;
        if (with_tol) {
            line.tol[i] = PARALLEL * sqrt(dot3(g[i], g[i])) * consts[MAX_SPEED];
        }
    }
    line.proper = true;
    return line;
}

// The ray's interval in a cell from its planes (render::cell's clip): near and far depth, the
// exit face; none where the ray misses the cell.
struct Clip {
    near: f64,
    far: f64,
    exit: u32,
    ok: bool,
}

fn clip_line(line: Line) -> Clip {
    var c = Clip(-consts[INFINITY], consts[INFINITY], 0u, false);
    for (var i = 0u; i < 4u; i++) {
        if (abs(line.b[i]) <= line.tol[i]) {
            if (line.a[i] < -1e-9lf) {
                return c;
            }
            continue;
        }
        let t = -line.a[i] / line.b[i];
        if (line.b[i] > 0.0lf) {
            if (t > c.near) {
                c.near = t;
            }
        } else if (t < c.far) {
            c.far = t;
            c.exit = i;
        }
    }
    c.ok = c.near < c.far;
    return c;
}

// Whether a cell reaches in front of the perspective near plane (render::footprint: its pixels
// then come from its planes, not from its faces).
fn near_clipped(tet: vec4<u32>) -> bool {
    if (consts[ANY_NEAR] == 0.0lf) {
        return false;
    }
    let dmin = consts[DMIN];
    return -eye_of(tet.x).z < dmin || -eye_of(tet.y).z < dmin || -eye_of(tet.z).z < dmin || -eye_of(tet.w).z < dmin;
}

// What a near-clipped cell gives a pixel (RayCell::interval from the planes, clipped to the
// camera's range), and where the march goes on: into the neighbour across its exit face,
// unless that one is near-clipped too (it has an entry of its own) or there is none.
struct NearStep {
    c: Contribution,
    next: u32,
    d_next: f64,
}

fn near_step(cell: u32, p: vec2<f64>, dmax: f64, speed: f64) -> NearStep {
    var r = NearStep(Contribution(vec3<f64>(0.0lf), 1.0lf), NO_NEIGHBOR, 0.0lf);
    let tet = mesh_at(2u * cell);
    let line = cell_line(tet, p, true);
    let iv = clip_line(line);
    if (!line.proper || !iv.ok) {
        return r;
    }
    let near = max(iv.near, consts[DMIN]);
    let far = min(iv.far, dmax);
    if (near < far) {
        r.c = contribution(tet, line, near, far, (far - near) * speed);
    }
    let next = mesh_at(2u * cell + 1u)[iv.exit];
    if (next != NO_NEIGHBOR && !near_clipped(mesh_at(2u * next))) {
        r.next = next;
        r.d_next = hit(tet, iv.exit, p).x;
    }
    return r;
}

// interpolateCoeff's (η, χ) at barycentric coordinates l from the coefficients mapped at the
// nodes (approx::interpolate_coeff::interpolate; interpolateColor maps the nodes' field here).
fn interpolate(tet: vec4<u32>, l: vec4<f64>) -> vec4<f64> {
    var r = vec4<f64>(0.0lf);
    for (var i = 0u; i < 4u; i++) {
        let at = node_at(tet[i]) + 6u;
        if (consts[METHOD] == METHOD_COLOR) {
            r = r + l[i] * map_field(nodes[at]);
        } else {
            r = r + l[i] * vec4<f64>(nodes[at], nodes[at + 1u], nodes[at + 2u], nodes[at + 3u]);
        }
    }
    return r;
}

// A cell's (b, θ) between depths near and far (length: the ray's length there): `exact linear 0`
// (Exact::transfer_pixel), `interpolateCoeff linear` (InterpolateCoeff::pixel) or, for a
// near-clipped cell, interpolateColor's constEA.
fn contribution(tet: vec4<u32>, line: Line, near: f64, far: f64, length: f64) -> Contribution {
    if (consts[METHOD] == METHOD_EXACT) {
        let v = vec4<f64>(nodes[node_at(tet.x) + 6u], nodes[node_at(tet.y) + 6u], nodes[node_at(tet.z) + 6u], nodes[node_at(tet.w) + 6u]);
        let s0 = line.a.x * v.x + line.a.y * v.y + line.a.z * v.z + line.a.w * v.w;
        let slope = line.b.x * v.x + line.b.y * v.y + line.b.z * v.z + line.b.w * v.w;
        return cell_contribution(s0 + far * slope, s0 + near * slope, length);
    }
    let f = interpolate(tet, line.a + far * line.b);
    let n = interpolate(tet, line.a + near * line.b);
    if (consts[METHOD] == METHOD_COLOR) {
        // A near-clipped cell has no fan: constEA (InterpolateColor::pixel), η and χ at their
        // means, in the series (η̄·(1 − θ)/χ̄ is the linear rule of constant η̄ and χ̄).
        let eta = 0.5lf * (f.xyz + n.xyz);
        let chi = 0.5lf * (f.w + n.w);
        let m = segment(eta, eta, vec3<f64>(0.0lf), false, chi, chi, length);
        return Contribution(m.b * consts[BRIGHTNESS], m.theta);
    }
    let c = segment(f.xyz, n.xyz, vec3<f64>(0.0lf), false, f.w, n.w, length);
    return Contribution(c.b * consts[BRIGHTNESS], c.theta);
}

// The cells passed, written where the driver cut the loops (twin: LOOPS_CUT).
const LOOPS_CUT: f64 = -1.0lf;

// Whether every loop of this invocation ran to its end. lavapipe (llvmpipe's gallivm) counts
// the iterations of all the loops of a batch of invocations together and, past 65535
// (LP_MAX_TGSI_LOOP_ITERATIONS in Mesa), ends each loop after the iteration it is in, silently
// (docs/gpu.md). A loop of consts[LOOP_CHECK] = 2 iterations, run last, then runs once; the
// frame takes such pixels from the twin.
fn loops_ran() -> bool {
    let trips = u32(consts[LOOP_CHECK]);
    var n = 0u;
    for (var i = 0u; i < trips; i++) {
        n++;
    }
    return n == trips;
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
        var cell = 0u;
        var tet = vec4<u32>(0u);
        var d_in = 0.0lf;
        if ((lists[e] & NEAR_ENTRY) != 0u) {
            if (t < stop || steps > cells) {
                break;
            }
            steps++;
            let step = near_step(lists[e] & ~NEAR_ENTRY, p, dmax, speed);
            color = color + t * step.c.b;
            t = t * step.c.theta;
            if (step.next == NO_NEIGHBOR) {
                continue;
            }
            cell = step.next;
            tet = mesh_at(2u * cell);
            d_in = step.d_next;
        } else {
            cell = lists[e] >> 2u;
            tet = mesh_at(2u * cell);
            d_in = hit(tet, lists[e] & 3u, p).x;
        }
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
            let near = max(d_in, dmin);
            let far = min(d_out, dmax);
            if (near < far && consts[METHOD] == METHOD_COLOR) {
                let c = color_contribution(cell, tet, p, near, far, d_out - d_in);
                color = color + t * c.b;
                t = t * c.theta;
            } else if (near < far) {
                let line = cell_line(tet, p, false);
                if (line.proper) {
                    let c = contribution(tet, line, near, far, (far - near) * speed);
                    color = color + t * c.b;
                    t = t * c.theta;
                }
            }
            let next = mesh_at(2u * cell + 1u)[x];
            if (next == NO_NEIGHBOR || near_clipped(mesh_at(2u * next))) {
                break;
            }
            cell = next;
            tet = mesh_at(2u * cell);
            d_in = out.x;
        }
    }
    image[5u * pix] = color.x;
    image[5u * pix + 1u] = color.y;
    image[5u * pix + 2u] = color.z;
    image[5u * pix + 3u] = t;
    image[5u * pix + 4u] = select(LOOPS_CUT, f64(steps), loops_ran());
}
