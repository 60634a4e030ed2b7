// Instanced, lit meshes: a key light, a sky/ground hemisphere fill and a little specular.

struct Globals {
    view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    light: vec4<f32>,
    up: vec4<f32>,
};

@group(0) @binding(0) var<uniform> g: Globals;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) m0: vec4<f32>,
    @location(3) m1: vec4<f32>,
    @location(4) m2: vec4<f32>,
    @location(5) m3: vec4<f32>,
    @location(6) colour: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) colour: vec4<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let model = mat4x4<f32>(v.m0, v.m1, v.m2, v.m3);
    let world = model * vec4<f32>(v.position, 1.0);
    var out: VertexOut;
    out.clip = g.view_proj * world;
    out.world = world.xyz;
    // Right for rotations, uniform scales and axis-aligned faces under any scale (cuboids).
    out.normal = (model * vec4<f32>(v.normal, 0.0)).xyz;
    out.colour = v.colour;
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var n = normalize(in.normal);
    if (!front) {
        n = -n;
    }
    let l = normalize(g.light.xyz);
    let v = normalize(g.eye.xyz - in.world);
    let h = normalize(l + v);
    let diffuse = max(dot(n, l), 0.0);
    let hemi = 0.5 + 0.5 * dot(n, normalize(g.up.xyz));
    let spec = pow(max(dot(n, h), 0.0), 48.0) * 0.3;
    let rgb = in.colour.rgb * (0.16 + 0.24 * hemi + 0.68 * diffuse) + vec3<f32>(spec);
    return vec4<f32>(rgb, 1.0);
}
