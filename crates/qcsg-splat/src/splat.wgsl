// The splat renderer's shaders (paper 000 §6, §6.1).
//
// Every splat is drawn as the back faces of a box aligned with the surface at its sample; each
// fragment ray-traces the sample's own quadric locally, keeps the hit nearest the eye that lies
// within the splat radius of the sample and inside every quadric of its clip list, and writes
// the hit's exact ray parameter as depth together with the quadric and term ids.
//
// Precision (§6: f64 on the CPU, f32 only relative to a local origin): positions reach the GPU
// relative to the eye, the own quadric relative to the sample, and clip quadrics relative to
// their own local origins, so no f32 quantity carries a world coordinate.

struct View {
    // xyz: the camera's unit right vector; w: 1 / (half height · aspect).
    right: vec4<f32>,
    // xyz: the camera's unit up vector; w: 1 / half height.
    up: vec4<f32>,
    // xyz: the unit viewing direction; w: 1 for perspective, 0 for orthographic projection.
    forward: vec4<f32>,
    // x: near, y: far ray parameter of the depth range, z: 1 / (far − near).
    depth: vec4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;
// Four vec4 per quadric: (a, b, c, d), (e, f, g, h), (i, j, 0, 0), (origin − eye, 0).
@group(0) @binding(1) var<storage, read> quadrics: array<vec4<f32>>;
// The clip lists, concatenated.
@group(0) @binding(2) var<storage, read> clip_indices: array<u32>;

struct Instance {
    // xyz: the sample relative to the eye; w: the splat radius.
    @location(0) centre_radius: vec4<f32>,
    // xyz: a unit tangent; w: the box's half extent along the normal.
    @location(1) tangent_height: vec4<f32>,
    // xyz: the unit normal of the quadric at the sample.
    @location(2) normal: vec4<f32>,
    // The own quadric about the sample: xyz its half-linear vector, w its constant.
    @location(3) linear_constant: vec4<f32>,
    // quadric, term, first clip index, clip count.
    @location(4) ids: vec4<u32>,
}

struct Varyings {
    @builtin(position) clip_position: vec4<f32>,
    // The fragment's point on the box, relative to the sample.
    @location(0) local: vec3<f32>,
    @location(1) @interpolate(flat) centre_radius: vec4<f32>,
    @location(2) @interpolate(flat) linear_constant: vec4<f32>,
    @location(3) @interpolate(flat) ids: vec4<u32>,
}

@vertex
fn vs_main(@builtin(vertex_index) corner: u32, instance: Instance) -> Varyings {
    let signs = vec3<f32>(
        f32(corner & 1u) * 2.0 - 1.0,
        f32((corner >> 1u) & 1u) * 2.0 - 1.0,
        f32((corner >> 2u) & 1u) * 2.0 - 1.0,
    );
    let n = instance.normal.xyz;
    let t1 = instance.tangent_height.xyz;
    let t2 = cross(n, t1);
    let r = instance.centre_radius.w;
    let local = signs.x * r * t1 + signs.y * r * t2 + signs.z * instance.tangent_height.w * n;
    let p = instance.centre_radius.xyz + local;
    let x = dot(p, view.right.xyz) * view.right.w;
    let y = dot(p, view.up.xyz) * view.up.w;
    let z = dot(p, view.forward.xyz);
    let near = view.depth.x;
    let far = view.depth.y;
    var out: Varyings;
    if view.forward.w > 0.5 {
        out.clip_position = vec4<f32>(x, y, (z - near) * far / (far - near), z);
    } else {
        out.clip_position = vec4<f32>(x, y, (z - near) * view.depth.z, 1.0);
    }
    out.local = local;
    out.centre_radius = instance.centre_radius;
    out.linear_constant = instance.linear_constant;
    out.ids = instance.ids;
    return out;
}

struct Quadric {
    a: mat3x3<f32>,
    l: vec3<f32>,
    j: f32,
    origin: vec3<f32>,
}

fn load_quadric(index: u32) -> Quadric {
    let k0 = quadrics[4u * index];
    let k1 = quadrics[4u * index + 1u];
    let k2 = quadrics[4u * index + 2u];
    let k3 = quadrics[4u * index + 3u];
    var q: Quadric;
    // Columns of the symmetric matrix [[a, d, e], [d, b, f], [e, f, c]].
    q.a = mat3x3<f32>(
        vec3<f32>(k0.x, k0.w, k1.x),
        vec3<f32>(k0.w, k0.y, k1.y),
        vec3<f32>(k1.x, k1.y, k0.z),
    );
    q.l = vec3<f32>(k1.z, k1.w, k2.x);
    q.j = k2.y;
    q.origin = k3.xyz;
    return q;
}

// Whether the point `p` (relative to the eye) lies inside every quadric of the clip list.
fn inside_clip_list(p: vec3<f32>, first: u32, count: u32) -> bool {
    for (var k = 0u; k < count; k = k + 1u) {
        let q = load_quadric(clip_indices[first + k]);
        let x = p - q.origin;
        let value = dot(x, q.a * x + 2.0 * q.l) + q.j;
        if value > 0.0 {
            return false;
        }
    }
    return true;
}

// The ray parameter goes out as the bits of an f32 (`DEPTH_T_FORMAT` is an integer format,
// which every backend can render to).
struct Target {
    @location(0) t: u32,
    @location(1) ids: vec2<u32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs_main(in: Varyings) -> Target {
    let centre = in.centre_radius.xyz;
    let radius = in.centre_radius.w;
    let from_eye = centre + in.local;
    var direction: vec3<f32>;
    var t_fragment: f32;
    if view.forward.w > 0.5 {
        t_fragment = length(from_eye);
        direction = from_eye / t_fragment;
    } else {
        direction = view.forward.xyz;
        t_fragment = dot(from_eye, direction);
    }

    // The own quadric about the sample: q(x) = xᵀAx + 2 lᵀx + j; the ray is local + u · direction.
    let own = load_quadric(in.ids.x);
    let l = in.linear_constant.xyz;
    let j = in.linear_constant.w;
    let p0 = in.local;
    let a = dot(direction, own.a * direction);
    let b = dot(direction, own.a * p0 + l);
    let c = dot(p0, own.a * p0 + 2.0 * l) + j;
    let discriminant = b * b - a * c;
    if discriminant < 0.0 {
        discard;
    }
    // Stable roots: k / a and c / k with k = −(b + sign(b) √disc); a plane has only c / k.
    let k = -(b + select(-1.0, 1.0, b >= 0.0) * sqrt(discriminant));
    var u0 = c / k;
    var u1 = k / a;
    if k == 0.0 {
        u0 = u1;
    }
    if a == 0.0 {
        u1 = u0;
    }
    let u_near = min(u0, u1);
    let u_far = max(u0, u1);

    var found = false;
    var u = 0.0;
    for (var attempt = 0u; attempt < 2u; attempt = attempt + 1u) {
        let candidate = select(u_far, u_near, attempt == 0u);
        let hit = p0 + candidate * direction;
        let t = t_fragment + candidate;
        // Also rejects NaN and infinite roots.
        if !(t > 0.0) || !(dot(hit, hit) <= radius * radius) {
            continue;
        }
        if inside_clip_list(centre + hit, in.ids.z, in.ids.w) {
            found = true;
            u = candidate;
            break;
        }
    }
    if !found {
        discard;
    }
    let t = t_fragment + u;
    var out: Target;
    out.t = bitcast<u32>(t);
    out.ids = in.ids.xy;
    out.depth = clamp((t - view.depth.x) * view.depth.z, 0.0, 1.0);
    return out;
}
