"""Renders one of our scene files with Blender's Cycles, direct light or up
to K bounces (--bounces), under a lattice exported by `adaptive-cpca envmap`
and/or local lights (--light, as `relight` takes them), and compares the
result with our dense relight of the same scene.

Run by scripts/cycles/compare.sh inside Blender:
  blender -b --factory-startup --python render_cycles.py -- \
      --scene S.json --width W --height H --env lattice.exr --ours ours.exr \
      --out cycles.exr --samples N --seed S [--bounces K] [--camera EYE,TARGET,UP,FOV] \
      [--light SPEC ...] [--closed-form]
or, for scripts/cycles/labels.sh, with --passes instead of --ours: the Normal,
Depth and DiffCol passes into --out as a multilayer EXR.

The fairness rules of the fair-comparison rules of docs/design.md section 7: the same
geometry (our Y-up world is Blender's (x, -z, y)), a pinhole camera with our
vertical field of view, the lattice's piecewise-constant radiance with
Closest lookup, Diffuse and Glossy (GGX) BSDFs with our parameters instead of
the importers' Principled ones, K total, diffuse and glossy bounces with
clamping off and caustics on, a one-pixel box filter and a transparent film
(alpha = coverage).
"""

import argparse
import json
import math
import os
import sys

import bpy
import mathutils
import numpy as np

# Our Y-up world -> Blender's Z-up: (x, y, z) -> (x, -z, y).
TO_BLENDER = mathutils.Matrix(((1, 0, 0, 0), (0, 0, -1, 0), (0, 1, 0, 0), (0, 0, 0, 1)))


def vec(v):
    return (TO_BLENDER @ mathutils.Vector((v[0], v[1], v[2], 1.0))).to_3d()


def direction(v):
    return (TO_BLENDER.to_3x3() @ mathutils.Vector(v)).normalized()


def scene_parser():
    """The arguments after Blender's `--`, and a parser of the scene and image
    size every render takes."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--scene", required=True)
    p.add_argument("--width", type=int, required=True)
    p.add_argument("--height", type=int, required=True)
    return p, argv


def parse_args():
    p, argv = scene_parser()
    p.add_argument("--camera", help="eye,target,up as 9 numbers then fov (ours after framing)")
    p.add_argument("--env", required=True, help="lat-long EXR of the lattice, or none (black)")
    p.add_argument("--light", action="append", default=[],
                   help="a local light as `relight --light` takes it (point or sphere)")
    p.add_argument("--closed-form", action="store_true",
                   help="also compare Cycles with the closed form of a sphere light over "
                        "the scene's one plane (diffuse, the light above its horizon)")
    p.add_argument("--ours", help="our dense relight, black background, EXR")
    p.add_argument("--also", action="append", default=[], metavar="NAME=EXR",
                   help="another image of ours (a model's relight) against the same render")
    p.add_argument("--out", required=True)
    p.add_argument("--samples", type=int, default=512)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--bounces", type=int, default=0, help="indirect bounces (ours: --bounces)")
    p.add_argument("--json", help="write the comparison here")
    p.add_argument("--passes", action="store_true",
                   help="write --out as a multilayer EXR with the Normal, Depth and DiffCol "
                        "passes (labels.sh compares them with our labels); no comparison")
    return p.parse_args(argv)


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)


# ---------------------------------------------------------------- materials


def texture_node(nodes, path):
    node = nodes.new("ShaderNodeTexImage")
    node.image = bpy.data.images.load(path)
    # 8-bit images are sRGB, float ones linear: what our loader assumes.
    node.image.colorspace_settings.name = "Linear" if node.image.is_float else "sRGB"
    node.interpolation = "Linear"  # bilinear between texel centres, as ours
    node.extension = "REPEAT"
    return node


def our_bsdf(material, spec, color_socket_source):
    """Replaces a material's nodes with ours: (1 - ks) Diffuse + ks Glossy GGX,
    both of colour `albedo` (x the texture), fed from `color_socket_source`
    (a function that links a colour into a socket) when given."""
    material.use_nodes = True
    tree = material.node_tree
    kept = {n.name for n in tree.nodes if n.type in ("TEX_IMAGE", "MIX_RGB", "MIX", "RGB",
                                                      "UVMAP", "TEX_COORD", "MAPPING",
                                                      "VECT_MATH", "MATH", "SEPRGB", "SEPARATE_COLOR")}
    for n in list(tree.nodes):
        if n.name not in kept:
            tree.nodes.remove(n)
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Roughness"].default_value = 0.0
    shader = diffuse
    kind = spec.get("type", "diffuse")
    if kind == "phong":
        raise SystemExit("Cycles has no Phong lobe: leave Phong scenes out of this comparison")
    color_inputs = [diffuse.inputs["Color"]]
    if kind == "ggx" and spec.get("specular", 0) > 0:
        glossy = tree.nodes.new("ShaderNodeBsdfGlossy")
        glossy.distribution = "GGX"
        # Cycles squares its roughness slider to get alpha.
        glossy.inputs["Roughness"].default_value = math.sqrt(spec["roughness"])
        color_inputs.append(glossy.inputs["Color"])
        mix = tree.nodes.new("ShaderNodeMixShader")
        mix.inputs["Fac"].default_value = spec["specular"]
        tree.links.new(diffuse.outputs["BSDF"], mix.inputs[1])
        tree.links.new(glossy.outputs["BSDF"], mix.inputs[2])
        shader = mix
    tree.links.new(shader.outputs[0], out.inputs["Surface"])
    for socket in color_inputs:
        color_socket_source(tree, socket)


def constant_color(albedo, texture=None):
    def link(tree, socket):
        if texture is None:
            socket.default_value = (albedo[0], albedo[1], albedo[2], 1.0)
            return
        image = texture_node(tree.nodes, texture)
        multiply = tree.nodes.new("ShaderNodeMixRGB")
        multiply.blend_type = "MULTIPLY"
        multiply.inputs["Fac"].default_value = 1.0
        multiply.inputs["Color2"].default_value = (albedo[0], albedo[1], albedo[2], 1.0)
        tree.links.new(image.outputs["Color"], multiply.inputs["Color1"])
        tree.links.new(multiply.outputs["Color"], socket)
    return link


def material_from(spec, base_dir, name):
    m = bpy.data.materials.new(name)
    texture = os.path.join(base_dir, spec["texture"]) if "texture" in spec else None
    albedo = spec.get("albedo", [1, 1, 1] if texture else [0.5, 0.5, 0.5])
    our_bsdf(m, spec, constant_color(albedo, texture))
    return m


def file_color_source(material):
    """What fed the importer's Principled 'Base Color': kept and re-linked."""
    tree = material.node_tree
    principled = next((n for n in tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
    if principled is None:
        return constant_color([0.6, 0.6, 0.6])
    socket = principled.inputs["Base Color"]
    if socket.is_linked:
        source = socket.links[0].from_socket
        return lambda tree, target: tree.links.new(source, target)
    return constant_color(list(socket.default_value)[:3])


# ---------------------------------------------------------------- geometry


def add_mesh_object(name, vertices, faces, uvs=None, smooth=False):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([vec(v) for v in vertices], [], faces)
    if uvs is not None:
        layer = mesh.uv_layers.new()
        for loop in mesh.loops:
            layer.data[loop.index].uv = uvs[loop.vertex_index]
    for poly in mesh.polygons:
        poly.use_smooth = smooth
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def add_plane(o, index, base_dir):
    # makeQuad of precompute/scene.cpp: the same corners and uv.
    n = mathutils.Vector(o["normal"]).normalized()
    helper = mathutils.Vector((0, 1, 0)) if abs(n.y) < 0.9 else mathutils.Vector((1, 0, 0))
    a = n.cross(helper).normalized() * (0.5 * o["size"])
    b = n.cross(a)
    c = mathutils.Vector(o["center"])
    corners = [c - a - b, c + a - b, c + a + b, c - a + b]
    uvs = [(1, 1), (0, 1), (0, 0), (1, 0)]
    obj = add_mesh_object(f"plane{index}", corners, [(0, 1, 2, 3)], uvs)
    obj.data.materials.append(material_from(o["material"], base_dir, f"plane{index}"))


def add_sphere(o, index, base_dir):
    # No analytic sphere in Blender: a fine UV sphere, smooth shaded.
    bpy.ops.mesh.primitive_uv_sphere_add(segments=512, ring_count=256, radius=o["radius"],
                                         location=vec(o["center"]))
    obj = bpy.context.active_object
    for poly in obj.data.polygons:
        poly.use_smooth = True
    obj.data.materials.append(material_from(o["material"], base_dir, f"sphere{index}"))


def our_transform(t):
    m = mathutils.Matrix.Identity(4)
    if not t:
        return m
    if "matrix" in t:
        v = t["matrix"]
        return mathutils.Matrix([v[0:4], v[4:8], v[8:12], v[12:16]])
    scale = t.get("scale", 1)
    scale = scale if isinstance(scale, list) else [scale] * 3
    s = mathutils.Matrix.Diagonal((*scale, 1))
    r = mathutils.Matrix.Rotation(math.radians(t.get("rotate_y_deg", 0)), 4, "Y")
    tr = mathutils.Matrix.Translation(t.get("translate", [0, 0, 0]))
    return tr @ r @ s


def import_model(path):
    before = set(bpy.data.objects)
    ext = os.path.splitext(path)[1].lower()
    if ext == ".obj":
        bpy.ops.wm.obj_import(filepath=path)
    elif ext in (".gltf", ".glb"):
        # Debian 12's Blender 3.4 glTF add-on still uses np.bool, which its
        # numpy (1.24) no longer has.
        if not hasattr(np, "bool"):
            np.bool = bool
        bpy.ops.import_scene.gltf(filepath=path)
    elif ext == ".dae":
        bpy.ops.wm.collada_import(filepath=path)
    elif ext == ".ply":
        bpy.ops.import_mesh.ply(filepath=path)
    else:
        raise SystemExit(f"{path}: no Blender importer wired for {ext}")
    new = [o for o in bpy.data.objects if o not in before]
    # Files bring their own lights and cameras (the Collada duck has both):
    # only the scene's lighting and camera count.
    for o in [o for o in new if o.type in ("LIGHT", "CAMERA")]:
        bpy.data.objects.remove(o)
    return [o for o in bpy.data.objects if o not in before and o.type == "MESH"]


def add_model(o, index, base_dir):
    path = os.path.join(base_dir, o["mesh"])
    objects = import_model(path)
    # Importers turn the file's Y-up into Z-up as we do; our transform acts in
    # Y-up, so it is conjugated by the axis change.
    ours = TO_BLENDER @ our_transform(o.get("transform")) @ TO_BLENDER.inverted()
    mode = o.get("normals", "file")
    for obj in objects:
        obj.matrix_world = ours @ obj.matrix_world
        mesh = obj.data
        if mode == "flat":
            for poly in mesh.polygons:
                poly.use_smooth = False
            if mesh.has_custom_normals:
                bpy.context.view_layer.objects.active = obj
                bpy.ops.mesh.customdata_custom_splitnormals_clear()
        elif mode == "smooth" or not mesh.has_custom_normals:
            for poly in mesh.polygons:
                poly.use_smooth = True
            mesh.use_auto_smooth = True
            mesh.auto_smooth_angle = math.radians(o.get("crease_angle", 60))
        if not obj.material_slots:
            obj.data.materials.append(bpy.data.materials.new(f"mesh{index}"))
        for slot in obj.material_slots:
            m = slot.material or bpy.data.materials.new(f"mesh{index}")
            slot.material = m
            spec = o.get("material")
            m.use_nodes = True
            if spec and ("albedo" in spec or "texture" in spec):
                texture = os.path.join(base_dir, spec["texture"]) if "texture" in spec else None
                our_bsdf(m, spec, constant_color(spec.get("albedo", [1, 1, 1]), texture))
            else:
                our_bsdf(m, spec or {"type": "diffuse"}, file_color_source(m))


# ---------------------------------------------------------------- camera, world, render


def add_camera(eye, target, up, fov, width, height):
    cam = bpy.data.cameras.new("camera")
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = math.radians(fov)
    cam.clip_start = 1e-4 * (mathutils.Vector(eye) - mathutils.Vector(target)).length
    cam.clip_end = 1e6
    obj = bpy.data.objects.new("camera", cam)
    bpy.context.scene.collection.objects.link(obj)
    forward = (vec(target) - vec(eye)).normalized()
    right = forward.cross(direction(up)).normalized()
    true_up = right.cross(forward)
    rotation = mathutils.Matrix((right, true_up, -forward)).transposed()
    obj.matrix_world = mathutils.Matrix.Translation(vec(eye)) @ rotation.to_4x4()
    scene = bpy.context.scene
    scene.camera = obj
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1


def add_world(env_path):
    world = bpy.data.worlds.new("lattice")
    bpy.context.scene.world = world
    world.use_nodes = True
    tree = world.node_tree
    tree.nodes.clear()
    if env_path is None:  # local lights alone: a black world
        out = tree.nodes.new("ShaderNodeOutputWorld")
        background = tree.nodes.new("ShaderNodeBackground")
        background.inputs["Strength"].default_value = 0.0
        tree.links.new(background.outputs["Background"], out.inputs["Surface"])
        return
    coords = tree.nodes.new("ShaderNodeTexCoord")
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.vector_type = "POINT"
    # Cycles centres an equirectangular map on +X and runs u towards -Y; ours
    # centres it on -Z (Blender's +Y) and runs u towards +X: a quarter turn.
    # The sun case of compare.sh checks it.
    mapping.inputs["Rotation"].default_value = (0, 0, math.radians(-90))
    image = tree.nodes.new("ShaderNodeTexEnvironment")
    image.image = bpy.data.images.load(env_path)
    image.image.colorspace_settings.name = "Linear"
    image.interpolation = "Closest"
    background = tree.nodes.new("ShaderNodeBackground")
    out = tree.nodes.new("ShaderNodeOutputWorld")
    tree.links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
    tree.links.new(mapping.outputs["Vector"], image.inputs["Vector"])
    tree.links.new(image.outputs["Color"], background.inputs["Color"])
    tree.links.new(background.outputs["Background"], out.inputs["Surface"])
    world.cycles.sampling_method = "MANUAL"
    world.cycles.sample_map_resolution = 2048


# ---------------------------------------------------------------- local lights


def parse_light(spec):
    """`relight --light` grammar (docs/lighting.md): kind, position, radius
    (sphere), emission (grey or RGB)."""
    kind, _, numbers = spec.partition(":")
    v = [float(x) for x in numbers.split(",")]
    if kind == "spot":
        raise SystemExit(f"{spec}: spot lights are left out of the Cycles comparison "
                         "(Blender's spot blend is not our smoothstep)")
    before = {"point": 3, "sphere": 4}.get(kind)
    if before is None or len(v) not in (before + 1, before + 3):
        raise SystemExit(f"{spec}: not point:X,Y,Z,I(,G,B) or sphere:X,Y,Z,RADIUS,L(,G,B)")
    emission = v[before:] * 3 if len(v) == before + 1 else v[before:]
    return {"kind": kind, "position": v[0:3], "radius": v[3] if kind == "sphere" else 0.0,
            "emission": emission}


def add_light(light, index):
    """Cycles' point lamp of power P (watts) has radiant intensity P / (4 pi);
    with a radius r it is sampled as a disc of radius r at its centre facing
    the shading point, of uniform radiance P / (4 pi * pi r^2). So our point
    light of intensity I is P = 4 pi I, and our sphere of radiance L is
    P = 4 pi^2 r^2 L. Blender 3.4's disc subtends pi r^2 / (d^2 + r^2) where
    the sphere subtends 2 pi (1 - sqrt(1 - r^2 / d^2)): a fraction about
    (r / d)^2 less light (0.25% at d = 20 r), which the closed-form plane
    check measures."""
    data = bpy.data.lights.new(f"lamp{index}", type="POINT")
    peak = max(light["emission"])
    data.color = [c / peak for c in light["emission"]] if peak > 0 else (1, 1, 1)
    r = light["radius"]
    data.energy = 4 * math.pi * peak if r == 0 else 4 * math.pi ** 2 * r * r * peak
    data.shadow_soft_size = r
    obj = bpy.data.objects.new(f"lamp{index}", data)
    obj.location = vec(light["position"])
    obj.visible_camera = False  # ours: lights light the scene, unseen
    bpy.context.scene.collection.objects.link(obj)


def camera_rays(eye, target, up, fov, width, height, per_side):
    """Our pinhole's rays (Y-up world) through per_side^2 stratified points of
    every pixel: origins and directions, shape (height, width, per_side^2, 3)."""
    eye, target, up = (np.array(x, dtype=np.float64) for x in (eye, target, up))
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    t = math.tan(math.radians(fov) / 2)
    offsets = (np.arange(per_side) + 0.5) / per_side
    sx = (np.arange(width)[:, None] + offsets[None, :]).reshape(-1)
    sy = (np.arange(height)[:, None] + offsets[None, :]).reshape(-1)
    x = (2 * sx / width - 1) * t * width / height
    y = (1 - 2 * sy / height) * t
    d = (forward[None, None] + x[None, :, None] * right[None, None]
         + y[:, None, None] * true_up[None, None])
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    d = d.reshape(height, per_side, width, per_side, 3).transpose(0, 2, 1, 3, 4)
    return eye, d.reshape(height, width, per_side * per_side, 3)


def closed_form_plane(scene_json, light, camera, width, height):
    """Radiance of a diffuse plane of albedo a under a point light of intensity
    I, a I cos(theta) / (pi D^2) at a point D from it, theta from the normal;
    or under a sphere of radiance L and radius r wholly above its horizon,
    a L (r / D)^2 cos(theta) (its irradiance is a point source's of intensity
    pi r^2 L). Per pixel, the mean over 8x8 samples; with a mask of pixels
    whose every sample meets the plane."""
    planes = [o for o in scene_json["objects"] if o.get("shape") == "plane"]
    if len(planes) != 1 or len(scene_json["objects"]) != 1:
        raise SystemExit("--closed-form needs a scene of one plane")
    plane = planes[0]
    material = plane["material"]
    if material.get("type", "diffuse") != "diffuse" or "texture" in material:
        raise SystemExit("--closed-form needs an untextured diffuse plane")
    n = np.array(plane["normal"], dtype=np.float64)
    n /= np.linalg.norm(n)
    c = np.array(plane["center"], dtype=np.float64)
    eye, dirs = camera_rays(*camera, width, height, 8)
    denom = dirs @ n
    t = ((c - eye) @ n) / np.where(np.abs(denom) > 1e-12, denom, np.nan)
    hit = eye + t[..., None] * dirs
    # The quad of add_plane: its in-plane axes a, b and half size.
    helper = np.array([0, 1, 0.0]) if abs(n[1]) < 0.9 else np.array([1, 0, 0.0])
    a = np.cross(n, helper)
    a /= np.linalg.norm(a)
    b = np.cross(n, a)
    half = 0.5 * plane["size"]
    rel = hit - c
    inside = (t > 0) & (np.abs(rel @ a) <= half) & (np.abs(rel @ b) <= half)
    centre = np.array(light["position"], dtype=np.float64)
    to_light = centre - hit
    dist = np.linalg.norm(to_light, axis=-1)
    cos_theta = (to_light @ n) / dist
    r = light["radius"]
    if not np.all(cos_theta[inside] * dist[inside] > r):
        raise SystemExit("--closed-form: the sphere dips below the plane's horizon somewhere")
    albedo = np.array(material.get("albedo", [0.5, 0.5, 0.5]), dtype=np.float64)
    per_sample = np.where(inside, r * r * cos_theta / dist ** 2 if r > 0
                          else cos_theta / (math.pi * dist ** 2), 0.0)
    radiance = per_sample.mean(axis=2)[..., None] * albedo * np.array(light["emission"])
    return radiance, inside.all(axis=2)


def compare_closed_form(expected, full, cycles_path, width, height):
    cycles = pixels(cycles_path, width, height)[..., :3]
    d = cycles[full] - expected[full]
    return {
        "relative_l2": float(np.sqrt((d ** 2).sum() / (expected[full] ** 2).sum())),
        "energy_ratio": float(cycles[full].sum() / expected[full].sum()),
        "pixels": int(full.sum()),
    }


def configure_cycles(samples, seed, bounces):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.seed = seed
    # Bounces K: total, diffuse and glossy; caustics on, so that glossy-to-diffuse
    # paths count as ours do.
    c.max_bounces = bounces
    c.diffuse_bounces = c.glossy_bounces = bounces
    c.transmission_bounces = c.volume_bounces = c.transparent_max_bounces = 0
    c.caustics_reflective = c.caustics_refractive = True
    c.sample_clamp_direct = 0
    c.sample_clamp_indirect = 0
    c.light_sampling_threshold = 0
    c.blur_glossy = 0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    scene.render.film_transparent = True
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.color_mode = "RGBA"


def pixels(path, width, height):
    image = bpy.data.images.load(path)
    image.colorspace_settings.name = "Linear"
    data = np.array(image.pixels[:], dtype=np.float64).reshape(height, width, image.channels)
    return data[::-1]  # Blender stores the bottom row first


def compare(ours_path, cycles_path, width, height):
    ours = pixels(ours_path, width, height)
    cycles = pixels(cycles_path, width, height)
    covered = cycles[..., 3] > 0
    full = cycles[..., 3] > 0.999
    edge = covered & ~full
    diff = ours[..., :3] - cycles[..., :3]

    def rel(mask):
        d = diff[mask]
        return float(np.sqrt((d ** 2).sum() / max((cycles[..., :3][mask] ** 2).sum(), 1e-300)))

    return {
        "relative_l2": rel(covered),
        "relative_l2_full_pixels": rel(full),
        "relative_l2_edge_pixels": rel(edge) if edge.any() else 0.0,
        "energy_ratio": float(ours[..., :3][covered].sum() / cycles[..., :3][covered].sum()),
        "covered_pixels": int(covered.sum()),
        "edge_pixels": int(edge.sum()),
    }


def build_scene(scene_path, width, height, camera=None):
    """The scene file's objects and camera (or `camera`: eye,target,up as 9
    numbers then fov) in an empty Blender scene; returns the scene's JSON and
    (eye, target, up, fov)."""
    with open(scene_path) as f:
        scene_json = json.load(f)
    base_dir = os.path.dirname(os.path.abspath(scene_path))
    reset()
    for i, o in enumerate(scene_json["objects"]):
        if "mesh" in o:
            add_model(o, i, base_dir)
        elif o["shape"] == "plane":
            add_plane(o, i, base_dir)
        else:
            add_sphere(o, i, base_dir)
    cam = scene_json["camera"]
    if camera:
        v = [float(x) for x in camera.split(",")]
        eye, target, up, fov = v[0:3], v[3:6], v[6:9], v[9]
    else:
        eye, target, up, fov = cam["eye"], cam["target"], cam["up"], cam["fov"]
    add_camera(eye, target, up, fov, width, height)
    return scene_json, (eye, target, up, fov)


def main():
    a = parse_args()
    scene_json, (eye, target, up, fov) = build_scene(a.scene, a.width, a.height, a.camera)
    add_world(None if a.env == "none" else os.path.abspath(a.env))
    lights = [parse_light(spec) for spec in a.light]
    for i, light in enumerate(lights):
        add_light(light, i)
    configure_cycles(a.samples, a.seed, a.bounces)
    for o in bpy.context.scene.objects:  # for the log: what Cycles renders
        print("object", o.name, o.type, [s.material.name for s in o.material_slots if s.material],
              tuple(round(v, 4) for v in o.dimensions))
    bpy.context.scene.render.filepath = os.path.abspath(a.out)
    if a.passes:  # the label passes beside Combined, one multilayer file
        layer = bpy.context.view_layer
        layer.use_pass_normal = layer.use_pass_z = layer.use_pass_diffuse_color = True
        bpy.context.scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
        bpy.ops.render.render(write_still=True)
        return
    bpy.ops.render.render(write_still=True)
    result = compare(os.path.abspath(a.ours), os.path.abspath(a.out), a.width, a.height)
    result.update({"scene": a.scene, "samples": a.samples, "seed": a.seed, "lights": a.light})
    for also in a.also:
        name, path = also.split("=", 1)
        result.setdefault("also", {})[name] = compare(os.path.abspath(path), os.path.abspath(a.out),
                                                      a.width, a.height)
    if a.closed_form:
        if len(lights) != 1 or a.env != "none":
            raise SystemExit("--closed-form needs one light and --env none")
        expected, full = closed_form_plane(scene_json, lights[0], (eye, target, up, fov),
                                           a.width, a.height)
        result["cycles_vs_closed_form"] = compare_closed_form(
            expected, full, os.path.abspath(a.out), a.width, a.height)
        result["ours_vs_closed_form"] = compare_closed_form(
            expected, full, os.path.abspath(a.ours), a.width, a.height)
    print("cycles-comparison " + json.dumps(result))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=2)


if __name__ == "__main__":  # render_olat.py imports the scene building
    main()
