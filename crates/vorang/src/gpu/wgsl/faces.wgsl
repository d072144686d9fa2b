// A face's depth and field value where a pixel's ray crosses it, from the face alone (its
// nodes in canonical order, ascending node number), so both cells of the face get the same
// bits: one cell's exit is the next one's entry. The depth is render::faces' expression term
// by term (plane for ordinary faces, double-double weights for slivers); the field value is
// interpolated with the same plane (perspective: of value/depth, then divided). Twins:
// gpu/twin.rs, faces.

struct Corner {
    p: vec2<f64>,
    // Depth (orthographic) or inverse depth (perspective).
    z: f64,
    // The field at the node.
    v: f64,
    id: u32,
}

// x with a NaN mapping to lo: render::faces' max_select/min_select.
fn clamp_select(x: f64, lo: f64, hi: f64) -> f64 {
    let m = select(lo, x, x > lo);
    return select(hi, m, m < hi);
}

fn dd_add(a: Dd, b: Dd) -> Dd {
    let s = two_sum(a.hi, b.hi);
    let t = s.lo + a.lo + b.lo;
    let q = s.hi + t;
    return Dd(q, t - (q - s.hi));
}

fn dd_mul(a: Dd, b: Dd) -> Dd {
    let p = two_prod(a.hi, b.hi);
    let e = p.lo + (a.hi * b.lo + a.lo * b.hi);
    let q = p.hi + e;
    return Dd(q, e - (q - p.hi));
}

fn dd_cross(u: vec2<f64>, v: vec2<f64>, p: vec2<f64>) -> Dd {
    let l = dd_mul(two_sum(u.x, -p.x), two_sum(v.y, -p.y));
    let r = dd_mul(two_sum(u.y, -p.y), two_sum(v.x, -p.x));
    return dd_add(l, Dd(-r.hi, -r.lo));
}

fn dd_weight(d: Dd, sign: f64) -> Dd {
    let s = Dd(sign * d.hi, sign * d.lo);
    if (s.hi + s.lo > 0.0lf) {
        return s;
    }
    return Dd(0.0lf, 0.0lf);
}

// (depth, field value) on the face through the three corners at screen position p.
fn face_hit(k0: Corner, k1: Corner, k2: Corner, p: vec2<f64>, persp: bool) -> vec2<f64> {
    var k = array<Corner, 3>(k0, k1, k2);
    // Canonical order: the swap network of render::faces.
    if (k[1].id < k[0].id) {
        let t = k[0];
        k[0] = k[1];
        k[1] = t;
    }
    if (k[2].id < k[1].id) {
        let t = k[1];
        k[1] = k[2];
        k[2] = t;
    }
    if (k[1].id < k[0].id) {
        let t = k[0];
        k[0] = k[1];
        k[1] = t;
    }
    let a = k[0].p;
    let b = k[1].p;
    let c = k[2].p;
    let z0 = k[0].z;
    let z1 = k[1].z;
    let z2 = k[2].z;
    let area = abs((a.x - c.x) * (b.y - c.y) - (a.y - c.y) * (b.x - c.x));
    let ab = (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y);
    let bc = (b.x - c.x) * (b.x - c.x) + (b.y - c.y) * (b.y - c.y);
    let ca = (c.x - a.x) * (c.x - a.x) + (c.y - a.y) * (c.y - a.y);
    let longest = max(max(ab, bc), ca);
    let sliver = area != area || area < 1e-3lf * longest;
    // The field's plane: of v (orthographic) or v/depth = v*z (perspective).
    var f = vec3<f64>(k[0].v, k[1].v, k[2].v);
    let vlo = min(min(f.x, f.y), f.z);
    let vhi = max(max(f.x, f.y), f.z);
    if (persp) {
        f = vec3<f64>(f.x * z0, f.y * z1, f.z * z2);
    }
    if (!sliver) {
        let zmin = min(min(z0, z1), z2);
        let zmax = max(max(z0, z1), z2);
        let e1 = b - a;
        let e2 = c - a;
        let d1 = z1 - z0;
        let d2 = z2 - z0;
        let det = e1.x * e2.y - e1.y * e2.x;
        let gx = (d1 * e2.y - d2 * e1.y) / det;
        let gy = (d2 * e1.x - d1 * e2.x) / det;
        let row = (z0 + gy * (p.y - a.y)) - gx * a.x;
        let z = clamp_select(row + gx * p.x, zmin, zmax);
        let f1 = f.y - f.x;
        let f2 = f.z - f.x;
        let hx = (f1 * e2.y - f2 * e1.y) / det;
        let hy = (f2 * e1.x - f1 * e2.x) / det;
        var value = ((f.x + hy * (p.y - a.y)) - hx * a.x) + hx * p.x;
        if (persp) {
            value = value / z;
            return vec2<f64>(1.0lf / z, clamp_select(value, vlo, vhi));
        }
        return vec2<f64>(z, clamp_select(value, vlo, vhi));
    }
    // A sliver: the screen barycentric weights in double-double (render::faces::sliver_depth).
    let sign = f64(orient(a, b, c));
    let w0 = dd_weight(dd_cross(b, c, p), sign);
    let w1 = dd_weight(dd_cross(c, a, p), sign);
    let w2 = dd_weight(dd_cross(a, b, p), sign);
    let sum = dd_add(dd_add(w0, w1), w2);
    let num = dd_add(dd_add(dd_mul(w0, Dd(z0, 0.0lf)), dd_mul(w1, Dd(z1, 0.0lf))), dd_mul(w2, Dd(z2, 0.0lf)));
    let ws = vec3<f64>(w0.hi + w0.lo, w1.hi + w1.lo, w2.hi + w2.lo);
    let wsum = ws.x + ws.y + ws.z;
    var n = num;
    var d = sum;
    if (persp) {
        n = sum;
        d = num;
    }
    if (d.hi + d.lo == 0.0lf) {
        let mean = (z0 + z1 + z2) / 3.0lf;
        let vmean = (k[0].v + k[1].v + k[2].v) / 3.0lf;
        if (persp) {
            return vec2<f64>(1.0lf / mean, vmean);
        }
        return vec2<f64>(mean, vmean);
    }
    let q = n.hi / d.hi;
    let r = dd_add(n, dd_neg(dd_mul(Dd(q, 0.0lf), d)));
    let depth = q + (r.hi + r.lo) / d.hi;
    var value = (ws.x * f.x + ws.y * f.y + ws.z * f.z) / wsum;
    if (persp) {
        value = value * depth;
    }
    if (wsum == 0.0lf) {
        value = (k[0].v + k[1].v + k[2].v) / 3.0lf;
    }
    return vec2<f64>(depth, clamp_select(value, vlo, vhi));
}

fn dd_neg(a: Dd) -> Dd {
    return Dd(-a.hi, -a.lo);
}

// The nodes of face f (opposite node f), counter-clockwise seen from outside (mesh::FACE_NODES).
fn face_node(f: u32, k: u32) -> u32 {
    let t = array<u32, 12>(1u, 2u, 3u, 0u, 3u, 2u, 0u, 1u, 3u, 0u, 2u, 1u);
    return t[3u * f + k];
}

// The exit face of a cell holding pixel centre p (which lies in the cell's footprint): the
// choice of render::faces::CellFaces (of the exit faces in face order, the first whose inner
// edges all hold p, else the last); 4 if the cell has no exit face.
fn exit_face(s: array<vec2<f64>, 4>, entry_sign: i32, p: vec2<f64>) -> u32 {
    var kind = array<i32, 4>(0, 0, 0, 0);
    var pos = array<vec3<u32>, 4>();
    for (var f = 0u; f < 4u; f++) {
        let l0 = face_node(f, 0u);
        let l1 = face_node(f, 1u);
        let l2 = face_node(f, 2u);
        let o = orient(s[l0], s[l1], s[l2]);
        kind[f] = o * entry_sign;
        pos[f] = select(vec3<u32>(l0, l2, l1), vec3<u32>(l0, l1, l2), o >= 0);
    }
    var last = 4u;
    for (var f = 0u; f < 4u; f++) {
        if (kind[f] < 0) {
            last = f;
        }
    }
    for (var f = 0u; f < 4u; f++) {
        if (kind[f] >= 0 || f == last) {
            continue;
        }
        var holds = true;
        for (var e = 0u; e < 3u; e++) {
            let u = pos[f][e];
            let v = pos[f][(e + 1u) % 3u];
            let other = 6u - f - u - v;
            if (kind[other] == kind[f] && !inside(s[u], s[v], p)) {
                holds = false;
            }
        }
        if (holds) {
            return f;
        }
    }
    return last;
}
