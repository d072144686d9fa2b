// interpolateColor (approx::interpolate_color; thesis 6.3.1): Shirley–Tuchman projected
// tetrahedra with Gouraud shading. The CPU prepares each cell's fan with its own code
// (gpu/frame.rs, fan_data: render::project's classification, the values θ and η̄ at the thick
// point T): FAN numbers per cell in `nodes` from consts[FANS] — θ_T, η̄_T (r, g, b), T on screen
// and the code of the fan's triangles. Per pixel the sectors are built and the winning one
// evaluated as render::gouraud's Fan::build and Fan::at, operation for operation. Twins:
// gpu/twin.rs, fan_at and color_contribution.

const FAN: u32 = 7u;
const THICK: u32 = 4u;
// The code's triangles 0..2 below this, triangle 3 and the count above it.
const FAN_SPLIT: f64 = 134217728.0lf;

fn fan_base(cell: u32) -> u32 {
    return u32(consts[FANS]) + FAN * cell;
}

// The code of a cell's fan as two words: triangles 0..2 (9 bits each, 3 per corner), then
// triangle 3 and the number of triangles.
fn fan_code(cell: u32) -> vec2<u32> {
    let code = nodes[fan_base(cell) + 6u];
    let hi = floor(code / FAN_SPLIT);
    return vec2<u32>(u32(code - hi * FAN_SPLIT), u32(hi));
}

fn fan_count(code: vec2<u32>) -> u32 {
    return code.y >> 9u;
}

// Corner m of triangle k: a node 0..3 or THICK.
fn fan_corner(code: vec2<u32>, k: u32, m: u32) -> u32 {
    if (k < 3u) {
        return (code.x >> (9u * k + 3u * m)) & 7u;
    }
    return (code.y >> (3u * m)) & 7u;
}

fn fan_pos(cell: u32, tet: vec4<u32>, v: u32) -> vec2<f64> {
    if (v == THICK) {
        let b = fan_base(cell);
        return vec2<f64>(nodes[b + 4u], nodes[b + 5u]);
    }
    return screen_of(tet[v]);
}

// [θ, η̄] at a fan vertex: θ = 1 and η mapped at a node, the prepared values at T.
fn fan_value(cell: u32, tet: vec4<u32>, v: u32) -> vec4<f64> {
    if (v == THICK) {
        let b = fan_base(cell);
        return vec4<f64>(nodes[b], nodes[b + 1u], nodes[b + 2u], nodes[b + 3u]);
    }
    let at = node_at(tet[v]) + 6u;
    return vec4<f64>(1.0lf, nodes[at], nodes[at + 1u], nodes[at + 2u]);
}

// One fan triangle (n_i, n_j, T): T's weight and n_j's as affine functions (c, x, y) of the
// pixel; not ok for a triangle without area.
struct Sector {
    thick: vec3<f64>,
    second: vec3<f64>,
    i: u32,
    j: u32,
    ok: bool,
}

fn sector(cell: u32, tet: vec4<u32>, code: vec2<u32>, k: u32) -> Sector {
    var s = Sector(vec3<f64>(0.0lf), vec3<f64>(0.0lf), 0u, 0u, false);
    var t = 2u;
    if (fan_corner(code, k, 0u) == THICK) {
        t = 0u;
    } else if (fan_corner(code, k, 1u) == THICK) {
        t = 1u;
    }
    s.i = fan_corner(code, k, (t + 1u) % 3u);
    s.j = fan_corner(code, k, (t + 2u) % 3u);
    let pi = fan_pos(cell, tet, s.i);
    let pj = fan_pos(cell, tet, s.j);
    let pt = fan_pos(cell, tet, THICK);
    let d = vec2<f64>(pj.x - pi.x, pj.y - pi.y);
    let e = vec2<f64>(pt.x - pi.x, pt.y - pi.y);
    let area = d.x * e.y - d.y * e.x;
    if (!(area != 0.0lf && abs(area) <= F64_MAX)) {
        return s;
    }
    s.thick = vec3<f64>((d.y * pi.x - d.x * pi.y) / area, -d.y / area, d.x / area);
    s.second = vec3<f64>((e.x * pi.y - e.y * pi.x) / area, e.y / area, -e.x / area);
    s.ok = true;
    return s;
}

// c + x·X + y·Y.
fn plane_at(q: vec3<f64>, p: vec2<f64>) -> f64 {
    return q.x + q.y * p.x + q.z * p.y;
}

// [θ, η̄] interpolated at pixel p: the sector where T's weight is smallest (Fan::at's
// comparisons over the sectors with area, in order, the rest +∞).
fn fan_at(cell: u32, tet: vec4<u32>, p: vec2<f64>) -> vec4<f64> {
    let code = fan_code(cell);
    var which = array<u32, 4>(0u, 0u, 0u, 0u);
    let inf = consts[INFINITY];
    var l = array<f64, 4>(inf, inf, inf, inf);
    var used = 0u;
    for (var k = 0u; k < fan_count(code); k++) {
        let s = sector(cell, tet, code, k);
        if (!s.ok) {
            continue;
        }
        which[used] = k;
        l[used] = plane_at(s.thick, p);
        used++;
    }
    var a = 0u;
    var la = l[0];
    if (l[1] < l[0]) {
        a = 1u;
        la = l[1];
    }
    var b = 2u;
    var lb = l[2];
    if (l[3] < l[2]) {
        b = 3u;
        lb = l[3];
    }
    var best = a;
    if (lb < la) {
        best = b;
    }
    var out = vec4<f64>(0.0lf);
    if (best >= used) {
        return out;
    }
    let s = sector(cell, tet, code, which[best]);
    let vi = fan_value(cell, tet, s.i);
    let vj = fan_value(cell, tet, s.j);
    let vt = fan_value(cell, tet, THICK);
    for (var c = 0u; c < 4u; c++) {
        let dt = vt[c] - vi[c];
        let dj = vj[c] - vi[c];
        let q = vec3<f64>(
            vi[c] + s.thick.x * dt + s.second.x * dj,
            s.thick.y * dt + s.second.y * dj,
            s.thick.z * dt + s.second.z * dj,
        );
        out[c] = plane_at(q, p);
    }
    return out;
}

// A fan cell's (b, θ) at pixel p over near..far of the ray's whole passage `full`: θ raised to
// the kept fraction where the interval is clipped (InterpolateColor::pixel), then
// render::gouraud's shade. Nothing for a cell without a fan (the CPU draws none).
fn color_contribution(cell: u32, tet: vec4<u32>, p: vec2<f64>, near: f64, far: f64, full: f64) -> Contribution {
    if (fan_count(fan_code(cell)) == 0u) {
        return Contribution(vec3<f64>(0.0lf), 1.0lf);
    }
    let v = fan_at(cell, tet, p);
    var theta = v.x;
    if (far - near < full) {
        theta = pow_frac(theta, (far - near) / full);
    }
    let k = consts[BRIGHTNESS] * (1.0lf - theta);
    return Contribution(vec3<f64>(v.y * k, v.z * k, v.w * k), theta);
}
