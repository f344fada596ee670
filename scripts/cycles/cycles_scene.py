"""Our scene files built in Blender for Cycles: the objects with our
materials, the camera, the lattice as the world and our local lights, and
the render settings of the fair comparison (docs/design.md section 7).
Imported by render_cycles.py and render_olat.py, inside Blender.

The same geometry (our Y-up world is Blender's (x, -z, y)), a pinhole
camera with our vertical field of view, the lattice's piecewise-constant
radiance with Closest lookup, Diffuse and Glossy (GGX) BSDFs with our
parameters instead of the importers' Principled ones, K total, diffuse and
glossy bounces with clamping off and caustics on, a one-pixel box filter and
a transparent film (alpha = coverage).
"""

import json
import math
import os

import bpy
import mathutils
import numpy as np

# Our Y-up world -> Blender's Z-up: (x, y, z) -> (x, -z, y).
TO_BLENDER = mathutils.Matrix(((1, 0, 0, 0), (0, 0, -1, 0), (0, 1, 0, 0), (0, 0, 0, 1)))


def vec(v):
    return (TO_BLENDER @ mathutils.Vector((v[0], v[1], v[2], 1.0))).to_3d()

def direction(v):
    return (TO_BLENDER.to_3x3() @ mathutils.Vector(v)).normalized()

def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)

def texture_node(nodes, path):
    node = nodes.new("ShaderNodeTexImage")
    node.image = bpy.data.images.load(path)
    # 8-bit images are sRGB, float ones linear: what our loader assumes.
    node.image.colorspace_settings.name = "Linear" if node.image.is_float else "sRGB"
    node.interpolation = "Linear"  # bilinear between texel centres, as ours
    node.extension = "REPEAT"
    return node

def ggx_alphas(spec):
    """Our GGX alphas along the tangent and bitangent (precompute/scene_json.cpp):
    roughness_u/v, or roughness made anisotropic as Cycles' Principled BSDF."""
    if "roughness_u" in spec:
        return spec["roughness_u"], spec["roughness_v"]
    a, t = spec["roughness"], spec.get("anisotropy", 0.0)
    if t == 0:
        return a, a
    aspect = math.sqrt(1 - 0.9 * t)
    return max(1e-3, a / aspect), max(1e-3, a * aspect)

def anisotropic_glossy(tree, alpha_u, alpha_v, rotation_deg, tangent_kind):
    """Cycles 3.4's Anisotropic BSDF with our two alphas: its roughness r and
    anisotropy A give alpha_x = r^2 (1 - A), alpha_y = r^2 / (1 - A) for A >= 0
    and r^2 / (1 + A), r^2 (1 + A) below (kernel/svm/closure.h), x along the
    tangent; the rotation in turns. The tangent is ours (docs/scenes.md,
    "Tangents"): about Z (our +Y) for spheres, from the UV map for meshes,
    world +X for planes; Cycles takes its part across the normal, as we do."""
    node = tree.nodes.new("ShaderNodeBsdfAnisotropic")
    r2 = math.sqrt(alpha_u * alpha_v)
    anisotropy = (1 - math.sqrt(alpha_u / alpha_v) if alpha_v >= alpha_u
                  else math.sqrt(alpha_v / alpha_u) - 1)
    node.inputs["Roughness"].default_value = math.sqrt(r2)
    node.inputs["Anisotropy"].default_value = anisotropy
    node.inputs["Rotation"].default_value = (rotation_deg / 360.0) % 1.0
    if tangent_kind == "sphere":
        tangent = tree.nodes.new("ShaderNodeTangent")
        tangent.direction_type = "RADIAL"
        tangent.axis = "Z"
        socket = tangent.outputs["Tangent"]
    elif tangent_kind == "uv":
        tangent = tree.nodes.new("ShaderNodeTangent")
        tangent.direction_type = "UV_MAP"
        socket = tangent.outputs["Tangent"]
    else:  # a plane: world +X, +Z (Blender's -Y) where its normal is along X
        along = tree.nodes.new("ShaderNodeCombineXYZ")
        x_normal = tangent_kind == "plane-x"
        along.inputs["X"].default_value = 0.0 if x_normal else 1.0
        along.inputs["Y"].default_value = -1.0 if x_normal else 0.0
        socket = along.outputs["Vector"]
    tree.links.new(socket, node.inputs["Tangent"])
    return node

def our_bsdf(material, spec, color_socket_source, tangent_kind="plane"):
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
    if kind == "ashikhmin-shirley":
        raise SystemExit("Cycles' Ashikhmin-Shirley is a microfacet distribution, not the paper's "
                         "BRDF: leave ashikhmin-shirley scenes out of this comparison")
    if kind == "ggx" and spec.get("specular", 0) > 0:
        alpha_u, alpha_v = ggx_alphas(spec)
        if alpha_u == alpha_v:
            glossy = tree.nodes.new("ShaderNodeBsdfGlossy")
            # Cycles squares its roughness slider to get alpha.
            glossy.inputs["Roughness"].default_value = math.sqrt(alpha_u)
        else:
            glossy = anisotropic_glossy(tree, alpha_u, alpha_v, spec.get("rotation", 0.0),
                                        tangent_kind)
        glossy.distribution = "GGX"
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

def material_from(spec, base_dir, name, tangent_kind="plane"):
    m = bpy.data.materials.new(name)
    texture = os.path.join(base_dir, spec["texture"]) if "texture" in spec else None
    albedo = spec.get("albedo", [1, 1, 1] if texture else [0.5, 0.5, 0.5])
    our_bsdf(m, spec, constant_color(albedo, texture), tangent_kind)
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
    along_x = abs(o["normal"][1]) < 1e-12 * abs(o["normal"][0]) and abs(o["normal"][2]) < 1e-12 * abs(o["normal"][0])
    obj.data.materials.append(material_from(o["material"], base_dir, f"plane{index}",
                                            "plane-x" if along_x else "plane"))

def add_sphere(o, index, base_dir):
    # No analytic sphere in Blender: a fine UV sphere, smooth shaded.
    bpy.ops.mesh.primitive_uv_sphere_add(segments=512, ring_count=256, radius=o["radius"],
                                         location=vec(o["center"]))
    obj = bpy.context.active_object
    for poly in obj.data.polygons:
        poly.use_smooth = True
    obj.data.materials.append(material_from(o["material"], base_dir, f"sphere{index}", "sphere"))

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
                our_bsdf(m, spec, constant_color(spec.get("albedo", [1, 1, 1]), texture), "uv")
            else:
                our_bsdf(m, spec or {"type": "diffuse"}, file_color_source(m), "uv")

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

def add_sun(index, towards_light, irradiance, radius_deg=0.0):
    """A sun whose light arrives from `towards_light` (our axes, towards the light)
    with RGB irradiance `irradiance` on a surface facing it: Blender's sun
    shines along its local -Z. Of angle 0 it is a distant point light; of
    angle 2 radius_deg Blender 3.4 samples a cone of that half-angle and each
    sample carries the strength, so a surface facing it gets the strength
    whatever the angle (a cap of radiance L is L pi sin^2(radius))."""
    data = bpy.data.lights.new(f"sun{index}", type="SUN")
    data.angle = math.radians(2 * radius_deg)
    peak = max(irradiance)
    data.energy = peak
    data.color = [c / peak for c in irradiance]
    obj = bpy.data.objects.new(f"sun{index}", data)
    obj.rotation_euler = direction(towards_light).to_track_quat("Z", "Y").to_euler()
    bpy.context.scene.collection.objects.link(obj)
    return obj


def add_map_sources(sources):
    """A map's sources as `envmap --json` lists them (direction, radius_deg,
    RGB radiance), each a sun of its angle and irradiance."""
    for k, s in enumerate(sources):
        cap = math.pi * math.sin(math.radians(s["radius_deg"])) ** 2
        add_sun(k, s["direction"], [cap * c for c in s["radiance"]], s["radius_deg"])


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
