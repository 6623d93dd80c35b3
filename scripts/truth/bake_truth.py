# Path-traced ground truth for ahdpack's accuracy table (docs/accuracy-real-lighting.md).
#
#   apt-get install blender python3-numpy        # Debian's Blender 3.4 (Cycles on the CPU)
#   blender -b --python scripts/truth/bake_truth.py -- --scene area --out tests/data/truth/area
#
# Builds a small scene (room with an area light, or a sun through a window), gives it a lightmap UV
# set, and bakes with Cycles, per lightmap texel, the irradiance E/pi for each of a fixed set of
# tangent-space normals (tilted in the tangent frame of the lightmap UVs), plus the irradiance at a
# bumpy "normal-mapped" normal field and the tangent-space normals Cycles used for it. `ahdpack
# report truth DIR` turns the training normals into a baker-like SH lightmap and measures every
# representation against the held-out ones.
#
# Why custom split normals and not a Normal Map node: Cycles multiplies diffuse closures whose
# normal differs from the shader-wide normal by a bump "shadow terminator" term (Chiang et al.
# 2019), 2.6 % low at a 37 degree tilt with a light 44 degrees off the surface normal: that is
# Cycles' shading, not the irradiance an engine's lightmap decode reproduces. Custom normals make
# the tilted normal the shader-wide one, so no term applies (E matches n.l exactly under a sun,
# to 2e-5). Only the baked point sees the tilt (Light Path "Is Camera Ray"); every other ray sees
# the wall's true normal, so bounced light is the untilted scene's.
#
# Output, in --out: truth.json (sizes, normals, which are held out) and truth.bin: little-endian
# float16 planes, in this order, each width*height*3 (RGB, row 0 = top of the image, v = 1):
#   the E/pi bake of each normal of "normals" in turn; then "bumped" (E/pi at the bumped normals);
#   then "bumped_normals" (their tangent-space xyz); then "coverage" (1 where a chart covers the
#   texel centre, in all three channels).
import argparse
import json
import math
import os
import sys

import bpy
import mathutils
import numpy as np


# The scenes (docs/accuracy-real-lighting.md "The corpus"): the room lit by an area light or a sun
# through a window; a Cornell box (open front) with a ceiling area light or a sun and sky through
# its open side; the room lit by several small coloured lamps; the room lit only by emissive
# surfaces with saturated walls (coloured bounce).
SCENES = ["area", "sun", "cornell_area", "cornell_sun", "lamps", "emissive"]


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--scene", choices=SCENES, required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--size", type=int, default=64)
    p.add_argument("--samples", type=int, default=128)
    p.add_argument("--margin", type=float, default=0.04, help="smart UV project's island margin (gutters between charts)")
    p.add_argument("--glb", help="also export the scene as glTF (TEXCOORD_1 = lightmap UVs)")
    return p.parse_args(argv)


def tangent_normals(count, min_z):
    """count directions on the cap z >= min_z (Fibonacci spiral, equal area), z first."""
    out = [(0.0, 0.0, 1.0)]
    golden = math.pi * (3.0 - math.sqrt(5.0))
    for i in range(1, count):
        z = 1.0 - (1.0 - min_z) * (i + 0.5) / count
        r = math.sqrt(max(0.0, 1.0 - z * z))
        a = golden * i
        out.append((r * math.cos(a), r * math.sin(a), z))
    return out


def material(name, albedo, emission=None, strength=0.0):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    seen = nt.nodes.new("ShaderNodeBsdfDiffuse")    # what the baked point sees: the custom normal
    other = nt.nodes.new("ShaderNodeBsdfDiffuse")   # what every other ray sees: the true normal
    for d in (seen, other):
        d.inputs["Color"].default_value = (*albedo, 1.0)
    geo = nt.nodes.new("ShaderNodeNewGeometry")
    nt.links.new(geo.outputs["True Normal"], other.inputs["Normal"])
    path = nt.nodes.new("ShaderNodeLightPath")
    mix = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
    nt.links.new(other.outputs[0], mix.inputs[1])
    nt.links.new(seen.outputs[0], mix.inputs[2])
    if emission is None:
        nt.links.new(mix.outputs[0], out.inputs["Surface"])
        return mat
    em = nt.nodes.new("ShaderNodeEmission")  # lights the others; a DIFFUSE bake leaves it out
    em.inputs["Color"].default_value = (*emission, 1.0)
    em.inputs["Strength"].default_value = strength
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(mix.outputs[0], add.inputs[0])
    nt.links.new(em.outputs[0], add.inputs[1])
    nt.links.new(add.outputs[0], out.inputs["Surface"])
    return mat


def add_quad(verts, faces, mats, corners, mat, cuts):
    """A planar quad (corners counter-clockwise seen from its front) as a cuts x cuts grid."""
    a, b, c, d = [mathutils.Vector(p) for p in corners]
    base = len(verts)
    for j in range(cuts + 1):
        for i in range(cuts + 1):
            u, v = i / cuts, j / cuts
            verts.append(tuple(a.lerp(b, u).lerp(d.lerp(c, u), v)))
    for j in range(cuts):
        for i in range(cuts):
            k = base + j * (cuts + 1) + i
            faces.append((k, k + 1, k + cuts + 2, k + cuts + 1))
            mats.append(mat)


def add_box(verts, faces, mats, lo, hi, mat, cuts):
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    quads = [
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],  # top
        [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],  # -y
        [(x1, y1, z0), (x0, y1, z0), (x0, y1, z1), (x1, y1, z1)],  # +y
        [(x0, y1, z0), (x0, y0, z0), (x0, y0, z1), (x0, y1, z1)],  # -x
        [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],  # +x
    ]
    for q in quads:
        add_quad(verts, faces, mats, q, mat, cuts)


def add_turned_box(verts, faces, mats, centre, size, angle, mat, cuts):
    """A box standing on z = 0, turned by angle (radians) about its vertical axis."""
    cx, cy = centre
    sx, sy, sz = size
    ca, sa = math.cos(angle), math.sin(angle)

    def p(x, y, z):
        return (cx + ca * x - sa * y, cy + sa * x + ca * y, z)
    x0, x1, y0, y1 = -sx / 2, sx / 2, -sy / 2, sy / 2
    quads = [
        [p(x0, y0, sz), p(x1, y0, sz), p(x1, y1, sz), p(x0, y1, sz)],
        [p(x0, y0, 0), p(x1, y0, 0), p(x1, y0, sz), p(x0, y0, sz)],
        [p(x1, y1, 0), p(x0, y1, 0), p(x0, y1, sz), p(x1, y1, sz)],
        [p(x0, y1, 0), p(x0, y0, 0), p(x0, y0, sz), p(x0, y1, sz)],
        [p(x1, y0, 0), p(x1, y1, 0), p(x1, y1, sz), p(x1, y0, sz)],
    ]
    for q in quads:
        add_quad(verts, faces, mats, q, mat, cuts)


def finish_mesh(verts, faces, fmat, mats):
    me = bpy.data.meshes.new("room")
    me.from_pydata(verts, [], faces)
    for m in mats:
        me.materials.append(m)
    for p, m in zip(me.polygons, fmat):
        p.material_index = m
        p.use_smooth = True
    me.use_auto_smooth = True
    me.auto_smooth_angle = math.radians(30)
    ob = bpy.data.objects.new("room", me)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def set_world(sky):
    world = bpy.data.worlds.new("world")
    world.color = sky
    bpy.context.scene.world = world


def build_cornell(kind):
    """A Cornell box 2 x 2 x 2 (Z up, open at -y), red left and green right walls, a tall and a
    short box turned; a ceiling area light, or a low sun and a blue sky through the open side."""
    mats = [material("white", (0.73, 0.73, 0.73)), material("red", (0.63, 0.065, 0.05)),
            material("green", (0.14, 0.45, 0.09))]
    verts, faces, fmat = [], [], []
    W, H, cuts = 1.0, 2.0, 6
    add_quad(verts, faces, fmat, [(-W, -W, 0), (W, -W, 0), (W, W, 0), (-W, W, 0)], 0, cuts)   # floor
    add_quad(verts, faces, fmat, [(-W, W, H), (W, W, H), (W, -W, H), (-W, -W, H)], 0, cuts)   # ceiling
    add_quad(verts, faces, fmat, [(-W, W, 0), (-W, -W, 0), (-W, -W, H), (-W, W, H)], 1, cuts)  # -x red
    add_quad(verts, faces, fmat, [(W, -W, 0), (W, W, 0), (W, W, H), (W, -W, H)], 2, cuts)      # +x green
    add_quad(verts, faces, fmat, [(W, W, 0), (-W, W, 0), (-W, W, H), (W, W, H)], 0, cuts)      # +y back
    add_turned_box(verts, faces, fmat, (-0.35, 0.35), (0.6, 0.6, 1.2), math.radians(17), 0, 3)
    add_turned_box(verts, faces, fmat, (0.37, -0.3), (0.6, 0.6, 0.6), math.radians(-18), 0, 3)
    ob = finish_mesh(verts, faces, fmat, mats)
    if kind == "cornell_sun":
        bpy.ops.object.light_add(type="SUN", rotation=(math.radians(62), 0, math.radians(-25)))
        bpy.context.active_object.data.energy = 5.0
        bpy.context.active_object.data.angle = math.radians(0.5)
        set_world((0.15, 0.22, 0.4))
    else:
        bpy.ops.object.light_add(type="AREA", location=(0.0, 0.0, H - 0.005))
        bpy.context.active_object.data.size = 0.5
        bpy.context.active_object.data.energy = 60.0
        set_world((0.0, 0.0, 0.0))
    return ob


def build_scene(kind):
    if kind.startswith("cornell"):
        return build_cornell(kind)
    return build_room(kind)


def build_room(kind):
    """The room (4 x 4 x 2.5, Z up, inward faces), two boxes, and the scene's light."""
    mats = [material("white", (0.8, 0.8, 0.8)), material("red", (0.8, 0.12, 0.1)),
            material("green", (0.12, 0.7, 0.15))]
    if kind == "emissive":  # saturated walls for coloured bounce, two glowing surfaces
        mats = [material("orange", (0.85, 0.45, 0.1)), material("blue", (0.1, 0.2, 0.8)),
                material("magenta", (0.7, 0.1, 0.6)), material("white", (0.8, 0.8, 0.8)),
                material("strip", (0.8, 0.8, 0.8), (1.0, 0.85, 0.6), 12.0),
                material("glow", (0.8, 0.8, 0.8), (0.2, 0.9, 1.0), 6.0)]
    verts, faces, fmat = [], [], []
    W, H, cuts = 2.0, 2.5, 8
    add_quad(verts, faces, fmat, [(-W, -W, 0), (W, -W, 0), (W, W, 0), (-W, W, 0)], 0, cuts)   # floor
    add_quad(verts, faces, fmat, [(-W, W, H), (W, W, H), (W, -W, H), (-W, -W, H)], 0, cuts)   # ceiling
    add_quad(verts, faces, fmat, [(-W, W, 0), (-W, -W, 0), (-W, -W, H), (-W, W, H)], 1, cuts)  # -x red
    add_quad(verts, faces, fmat, [(W, -W, 0), (W, W, 0), (W, W, H), (W, -W, H)], 2, cuts)      # +x green
    add_quad(verts, faces, fmat, [(W, W, 0), (-W, W, 0), (-W, W, H), (W, W, H)], 0, cuts)      # +y back
    if kind == "sun":  # the -y wall with a window 1.6 wide, 1.0 high, sill at 1.0
        wx, z0, z1 = 0.8, 1.0, 2.0
        add_quad(verts, faces, fmat, [(-W, -W, 0), (-wx, -W, 0), (-wx, -W, H), (-W, -W, H)], 0, 4)
        add_quad(verts, faces, fmat, [(wx, -W, 0), (W, -W, 0), (W, -W, H), (wx, -W, H)], 0, 4)
        add_quad(verts, faces, fmat, [(-wx, -W, 0), (wx, -W, 0), (wx, -W, z0), (-wx, -W, z0)], 0, 4)
        add_quad(verts, faces, fmat, [(-wx, -W, z1), (wx, -W, z1), (wx, -W, H), (-wx, -W, H)], 0, 4)
    else:
        add_quad(verts, faces, fmat, [(-W, -W, 0), (W, -W, 0), (W, -W, H), (-W, -W, H)], 0, cuts)
    add_box(verts, faces, fmat, (-1.2, -0.2, 0), (-0.2, 0.8, 1.4), 0, 4)
    add_box(verts, faces, fmat, (0.3, -1.0, 0), (1.1, -0.2, 0.7), 0, 4)
    if kind == "emissive":  # a glowing strip high on the back wall and a glowing cube on the floor
        add_quad(verts, faces, fmat, [(0.9, W - 0.02, 1.9), (-0.9, W - 0.02, 1.9), (-0.9, W - 0.02, 2.1),
                                      (0.9, W - 0.02, 2.1)], 4, 1)
        add_box(verts, faces, fmat, (0.9, 0.6, 0), (1.3, 1.0, 0.4), 5, 2)
        fmat[:] = [{0: 3, 1: 1, 2: 2}.get(m, m) if i < 6 * cuts * cuts else m for i, m in enumerate(fmat)]
        fmat[:cuts * cuts] = [0] * (cuts * cuts)  # the floor orange
    ob = finish_mesh(verts, faces, fmat, mats)
    if kind == "lamps":  # four small lamps of different colours and heights (sharp shadows)
        for loc, col, watts in [((-1.4, -1.3, 0.5), (1.0, 0.55, 0.25), 40.0), ((1.5, 1.2, 2.1), (0.35, 0.5, 1.0), 70.0),
                                ((0.8, -1.5, 1.5), (0.5, 1.0, 0.45), 25.0), ((-0.6, 1.4, 2.3), (1.0, 1.0, 1.0), 50.0)]:
            bpy.ops.object.light_add(type="POINT", location=loc)
            bpy.context.active_object.data.energy = watts
            bpy.context.active_object.data.color = col
            bpy.context.active_object.data.shadow_soft_size = 0.03
        set_world((0.0, 0.0, 0.0))
        return ob
    if kind == "emissive":
        set_world((0.0, 0.0, 0.0))
        return ob
    if kind == "sun":
        bpy.ops.object.light_add(type="SUN", rotation=(math.radians(55), 0, math.radians(20)))
        bpy.context.active_object.data.energy = 4.0
        bpy.context.active_object.data.angle = math.radians(1.0)
        sky = (0.05, 0.07, 0.1)
    else:
        bpy.ops.object.light_add(type="AREA", location=(0.2, 0.3, H - 0.01))
        bpy.context.active_object.data.size = 1.0
        bpy.context.active_object.data.energy = 120.0
        sky = (0.0, 0.0, 0.0)
    world = bpy.data.worlds.new("world")
    world.color = sky
    bpy.context.scene.world = world
    return ob


def lightmap_uvs(ob, margin):
    me = ob.data
    me.uv_layers.new(name="uv")
    lm = me.uv_layers.new(name="lightmap")
    me.uv_layers.active = lm
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.uv.smart_project(angle_limit=math.radians(66), island_margin=margin)
    bpy.ops.object.mode_set(mode="OBJECT")


def frames(me):
    """Per loop (tangent, bitangent, normal) of the lightmap UVs: the frame the SH is stored in."""
    me.calc_normals_split()
    me.calc_tangents(uvmap="lightmap")
    out = []
    for l in me.loops:
        n = mathutils.Vector(l.normal)
        t = mathutils.Vector(l.tangent)
        out.append((t, l.bitangent_sign * n.cross(t), n))
    return out


def bumped(frame_list, me):
    """A bump pattern in the tangent frame: tilts up to ~30 degrees varying over the walls."""
    out = []
    for (t, b, n), l in zip(frame_list, me.loops):
        p = me.vertices[l.vertex_index].co
        s = 0.55 * math.sin(3.1 * (p.x + p.y) + 1.3 * p.z)
        c = 0.45 * math.cos(2.3 * p.z - 1.7 * p.x + 0.9 * p.y)
        out.append((t * s + b * c + n).normalized())
    return out


def bake(ob, img, kind):
    bpy.ops.object.select_all(action="DESELECT")
    ob.select_set(True)
    bpy.context.view_layer.objects.active = ob
    if kind == "NORMAL":
        r = bpy.ops.object.bake(type="NORMAL", normal_space="TANGENT", uv_layer="lightmap",
                                margin=0, use_clear=True)
    elif kind == "EMIT":
        r = bpy.ops.object.bake(type="EMIT", margin=0, use_clear=True)
    else:
        r = bpy.ops.object.bake(type="DIFFUSE", pass_filter={"DIRECT", "INDIRECT"},
                                margin=0, use_clear=True)
    assert "FINISHED" in r, r
    w, h = img.size
    px = np.array(img.pixels[:], dtype=np.float32).reshape(h, w, 4)[::-1, :, :3]  # row 0 = top
    return np.ascontiguousarray(px)


def tangent_socket(nt):
    tg = nt.nodes.new("ShaderNodeTangent")
    tg.direction_type = "UV_MAP"
    tg.uv_map = "lightmap"
    return tg.outputs["Tangent"]


def unit(v):
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-12)


def bake_vector(ob, img, socket_of):
    """Bakes a vector the shader sees (encoded as emission 0.5 v + 0.5; None: white) per texel,
    through every material, then restores the materials' surface links."""
    saved, encoded = [], False
    for m in ob.data.materials:
        nt = m.node_tree
        out = nt.nodes["Material Output"]
        saved.append((nt, out, out.inputs["Surface"].links[0].from_socket))
        em = nt.nodes.new("ShaderNodeEmission")
        em.inputs["Strength"].default_value = 1.0
        src = socket_of(nt)
        encoded = src is not None
        if encoded:
            ma = nt.nodes.new("ShaderNodeVectorMath")
            ma.operation = "MULTIPLY_ADD"
            nt.links.new(src, ma.inputs[0])
            ma.inputs[1].default_value = (0.5, 0.5, 0.5)
            ma.inputs[2].default_value = (0.5, 0.5, 0.5)
            nt.links.new(ma.outputs[0], em.inputs["Color"])
        else:
            em.inputs["Color"].default_value = (1, 1, 1, 1)
        nt.links.new(em.outputs[0], out.inputs["Surface"])
    v = bake(ob, img, "EMIT")
    for nt, out, src in saved:
        nt.links.new(src, out.inputs["Surface"])
    return v * 2.0 - 1.0 if encoded else v


def main():
    a = args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.cycles.samples = a.samples
    sc.cycles.use_denoising = False
    sc.cycles.seed = 1
    sc.render.bake.use_pass_color = False
    ob = build_scene(a.scene)
    lightmap_uvs(ob, a.margin)
    me = ob.data
    fr = frames(me)
    img = bpy.data.images.new("bake", a.size, a.size, float_buffer=True)
    for m in me.materials:
        tex = m.node_tree.nodes.new("ShaderNodeTexImage")
        tex.image = img
        m.node_tree.nodes.active = tex
    os.makedirs(a.out, exist_ok=True)
    if a.glb:
        os.makedirs(os.path.dirname(os.path.abspath(a.glb)), exist_ok=True)
        bpy.ops.export_scene.gltf(filepath=a.glb, export_format="GLB", export_normals=True,
                                  export_texcoords=True, export_materials="NONE")
    normals = tangent_normals(41, math.cos(math.radians(70)))
    held_out = [i for i in range(len(normals)) if i % 5 in (1, 3)]
    planes = []
    for k, n in enumerate(normals):
        me.normals_split_custom_set([(t * n[0] + b * n[1] + nn * n[2]).normalized() for t, b, nn in fr])
        planes.append(bake(ob, img, "DIFFUSE"))
        print(f"truth: normal {k + 1}/{len(normals)}", flush=True)
    me.normals_split_custom_set(bumped(fr, me))
    planes.append(bake(ob, img, "DIFFUSE"))
    nb = unit(bake_vector(ob, img, lambda nt: nt.nodes.new("ShaderNodeNewGeometry").outputs["Normal"]))
    me.normals_split_custom_set([nn for _, _, nn in fr])
    n = unit(bake_vector(ob, img, lambda nt: nt.nodes.new("ShaderNodeNewGeometry").outputs["True Normal"]))
    t = unit(bake_vector(ob, img, tangent_socket))
    b = np.cross(n, t)
    planes.append(np.stack([(nb * t).sum(-1), (nb * b).sum(-1), (nb * n).sum(-1)], axis=-1))
    cov = bake_vector(ob, img, lambda nt: None)  # emission of (1, 1, 1) where a chart is
    planes.append((cov[..., :1] > 0.5).astype(np.float32).repeat(3, axis=2))
    np.concatenate([p.reshape(-1) for p in planes]).astype("<f2").tofile(os.path.join(a.out, "truth.bin"))
    meta = {
        "format": "ahdpack-truth", "version": 1, "scene": a.scene, "width": a.size, "height": a.size,
        "samples": a.samples, "margin": a.margin, "value": "E/pi (Cycles DIFFUSE pass, direct + indirect, no colour)",
        "frame": "tangent frame of the lightmap UVs (x = dP/du, y = dP/dv, z = normal)",
        "normals": [list(n) for n in normals], "held_out": held_out,
        "planes": ["normal %d" % k for k in range(len(normals))] + ["bumped", "bumped_normals", "coverage"],
    }
    with open(os.path.join(a.out, "truth.json"), "w") as f:
        json.dump(meta, f, indent=1)
    print("truth: wrote", a.out)


main()
