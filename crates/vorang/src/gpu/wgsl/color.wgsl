// interpolateColor (approx::interpolate_color; thesis 6.3.1): Shirley–Tuchman projected
// tetrahedra with Gouraud shading. Per cell the CPU classifies the projection
// (render::project) and lists one word in `lists` from consts[FANS] (gpu/color.rs): the
// number of fan triangles (bits 0–2), the node at the thick point T (bits 3–4, bit 6 set) or
// that T is where two edges cross (bit 5), and per triangle k at bit 8 + 6k the position of T
// in it and its two nodes in the triangle's order after T. Per pixel the march finds T, the
// values θ and η̄ there (InterpolateColor::prepare), builds the fan's sectors and evaluates the
// winning one (render::gouraud's Fan::build and Fan::at), operation for operation. The nodes'
// η and χ are the transfer function at their field values (Transfer1D::map_nodes). Twins:
// gpu/twin/color.rs.

const THICK: u32 = 4u;

fn fan_code(cell: u32) -> u32 {
    return lists[u32(consts[FANS]) + cell];
}

fn fan_count(code: u32) -> u32 {
    return code & 7u;
}

// Node m (0: the first after T, 1: the second) of fan triangle k.
fn fan_node(code: u32, k: u32, m: u32) -> u32 {
    return (code >> (10u + 6u * k + 2u * m)) & 3u;
}

fn field_of(n: u32) -> f64 {
    return nodes[node_at(n) + 6u];
}

// (η, χ) at field value s (Transfer1D::eval).
fn map_field(s: f64) -> vec4<f64> {
    return eval_in(piece_of(s), s);
}

// [θ, η̄] at a node: θ = 1, η mapped at the node.
fn node_value(n: u32) -> vec4<f64> {
    let m = map_field(field_of(n));
    return vec4<f64>(1.0lf, m.x, m.y, m.z);
}

fn cross2(a: vec2<f64>, b: vec2<f64>) -> f64 {
    return a.x * b.y - a.y * b.x;
}

// T on screen: a node, or where edges ab and cd cross (render::project's classify_with).
fn thick_point(tet: vec4<u32>, code: u32) -> vec2<f64> {
    if ((code & 32u) == 0u) {
        return screen_of(tet[(code >> 3u) & 3u]);
    }
    let p = screen_of(tet[fan_node(code, 0u, 0u)]);
    let q = screen_of(tet[fan_node(code, 0u, 1u)]);
    let r = screen_of(tet[fan_node(code, 1u, 1u)]) - p;
    let u = screen_of(tet[fan_node(code, 2u, 1u)]) - q;
    let denom = r.x * u.y - r.y * u.x;
    let t = ((q.x - p.x) * u.y - (q.y - p.y) * u.x) / denom;
    return vec2<f64>(p.x + t * r.x, p.y + t * r.y);
}

// One end of T's ray: barycentric coordinates and depth.
struct End {
    lambda: vec4<f64>,
    d: f64,
}

// The cell's barycentric coordinates from screen-affine weights mu of nodes `at` (count n),
// perspective-corrected, and the depth there (Projection::thick_ends' `end`).
fn thick_end(at: vec3<u32>, mu: vec3<f64>, n: u32, depth: vec4<f64>) -> End {
    var e = End(vec4<f64>(0.0lf), 0.0lf);
    if (consts[PERSPECTIVE] != 0.0lf) {
        var total = 0.0lf;
        for (var m = 0u; m < n; m++) {
            total = total + mu[m] / depth[at[m]];
        }
        for (var m = 0u; m < n; m++) {
            e.lambda[at[m]] = mu[m] / depth[at[m]] / total;
        }
    } else {
        for (var m = 0u; m < n; m++) {
            e.lambda[at[m]] = mu[m];
        }
    }
    for (var m = 0u; m < n; m++) {
        e.d = e.d + e.lambda[at[m]] * depth[at[m]];
    }
    return e;
}

// [θ, η̄] at T (InterpolateColor::prepare): T's ray through the cell (Projection::thick_ends),
// η and χ mapped at its ends, θ = e^{−½(χ_near + χ_far)·ℓ} by the series (`segment`, whose θ is
// that for χ linear along the ray), η̄ = η_far·θ + η_near·(1 − θ).
fn thick_value(tet: vec4<u32>, code: u32, tp: vec2<f64>) -> vec4<f64> {
    let s = array<vec2<f64>, 4>(screen_of(tet.x), screen_of(tet.y), screen_of(tet.z), screen_of(tet.w));
    let depth = vec4<f64>(-eye_of(tet.x).z, -eye_of(tet.y).z, -eye_of(tet.z).z, -eye_of(tet.w).z);
    var a = End(vec4<f64>(0.0lf), 0.0lf);
    var b = a;
    if ((code & 32u) != 0u) {
        let na = fan_node(code, 0u, 0u);
        let nc = fan_node(code, 0u, 1u);
        let nb = fan_node(code, 1u, 1u);
        let nd = fan_node(code, 2u, 1u);
        let p = s[na];
        let r = s[nb] - s[na];
        let q = s[nc];
        let w = s[nd] - s[nc];
        let denom = cross2(r, w);
        if (denom == 0.0lf) {
            return vec4<f64>(1.0lf, 0.0lf, 0.0lf, 0.0lf);
        }
        let t = cross2(q - p, w) / denom;
        let u = cross2(q - p, r) / denom;
        a = thick_end(vec3<u32>(na, nb, 0u), vec3<f64>(1.0lf - t, t, 0.0lf), 2u, depth);
        b = thick_end(vec3<u32>(nc, nd, 0u), vec3<f64>(1.0lf - u, u, 0.0lf), 2u, depth);
    } else if ((code & 64u) != 0u) {
        let i = (code >> 3u) & 3u;
        let j = select(0u, 1u, i == 0u);
        let k = select(j + 1u, j + 2u, i == j + 1u);
        let l = select(k + 1u, k + 2u, i == k + 1u);
        let area = cross2(s[k] - s[j], s[l] - s[j]);
        if (area == 0.0lf) {
            return node_value(tet[i]);
        }
        let mj = cross2(s[k] - tp, s[l] - tp) / area;
        let mk = cross2(s[l] - tp, s[j] - tp) / area;
        a = thick_end(vec3<u32>(i, 0u, 0u), vec3<f64>(1.0lf, 0.0lf, 0.0lf), 1u, depth);
        b = thick_end(vec3<u32>(j, k, l), vec3<f64>(mj, mk, 1.0lf - mj - mk), 3u, depth);
    } else {
        return vec4<f64>(1.0lf, 0.0lf, 0.0lf, 0.0lf);
    }
    var near = a;
    var far = b;
    if (!(a.d <= b.d)) {
        near = b;
        far = a;
    }
    let v = vec4<f64>(field_of(tet.x), field_of(tet.y), field_of(tet.z), field_of(tet.w));
    let front = map_field(scalar4(v, near.lambda));
    let back = map_field(scalar4(v, far.lambda));
    let l = (far.d - near.d) * ray_speed(tp);
    let zero = vec3<f64>(0.0lf);
    let theta = segment(zero, zero, zero, false, back.w, front.w, l).theta;
    return vec4<f64>(
        theta,
        back.x * theta + front.x * (1.0lf - theta),
        back.y * theta + front.y * (1.0lf - theta),
        back.z * theta + front.z * (1.0lf - theta),
    );
}

// The field at barycentric coordinates l (Transfer1D::scalar).
fn scalar4(v: vec4<f64>, l: vec4<f64>) -> f64 {
    return l.x * v.x + l.y * v.y + l.z * v.z + l.w * v.w;
}

// World length per unit of depth along the ray through screen position p (Ray::speed of
// Projector::ray_at).
fn ray_speed(p: vec2<f64>) -> f64 {
    if (consts[PERSPECTIVE] == 0.0lf) {
        return 1.0lf;
    }
    let xn = 2.0lf * p.x / consts[WIDTH] - 1.0lf;
    let yn = 1.0lf - 2.0lf * p.y / consts[HEIGHT];
    let dx = xn * consts[TAN_X];
    let dy = yn * consts[TAN_Y];
    return sqrt(dx * dx + dy * dy + 1.0lf);
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

fn sector(tet: vec4<u32>, code: u32, k: u32, pt: vec2<f64>) -> Sector {
    var s = Sector(vec3<f64>(0.0lf), vec3<f64>(0.0lf), fan_node(code, k, 0u), fan_node(code, k, 1u), false);
    let pi = screen_of(tet[s.i]);
    let pj = screen_of(tet[s.j]);
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
fn fan_at(tet: vec4<u32>, code: u32, p: vec2<f64>) -> vec4<f64> {
    let pt = thick_point(tet, code);
    var which = array<u32, 4>(0u, 0u, 0u, 0u);
    let inf = consts[INFINITY];
    var l = array<f64, 4>(inf, inf, inf, inf);
    var used = 0u;
    for (var k = 0u; k < fan_count(code); k++) {
        let s = sector(tet, code, k, pt);
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
    let s = sector(tet, code, which[best], pt);
    let vi = node_value(tet[s.i]);
    let vj = node_value(tet[s.j]);
    let vt = thick_value(tet, code, pt);
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
    let code = fan_code(cell);
    if (fan_count(code) == 0u) {
        return Contribution(vec3<f64>(0.0lf), 1.0lf);
    }
    let v = fan_at(tet, code, p);
    var theta = v.x;
    if (far - near < full) {
        theta = pow_frac(theta, (far - near) / full);
    }
    let k = consts[BRIGHTNESS] * (1.0lf - theta);
    return Contribution(vec3<f64>(v.y * k, v.z * k, v.w * k), theta);
}
