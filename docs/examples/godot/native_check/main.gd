# Renders the placed scene `ahdpack scene` writes (res://conv/world.glb) twice, from the same camera,
# through the same Environment: lit by Godot's own LightmapGI from the source SH (native.png), and
# by the ahdpack add-on from the conversion's planes (addon.png). GodotNative.*
# (tests/judges/godot_native_lightmap_test.cpp) compares the two.
#
# The LightmapGIData is built here, as a baked scene's would be loaded: one Texture2DArray of
# 4 layers per page (L0, L1y, L1z, L1x) in Godot 4.4+'s packed directional form (res://native.bin,
# float RGB, written by the test from the Godot 4.2 bake), uses_spherical_harmonics, the packed
# flag (Godot 4.6 refuses unpacked directional data: scene/3d/lightmap_gi.cpp,
# NOTIFICATION_POST_ENTER_TREE), one probe point so the lightmap has bounds, and a user per mesh
# at the whole atlas (its TEXCOORD_1 is in atlas space) and its page.
extends Node

const H = preload("res://harness.gd")
const AhdLightmapScript = preload("res://addons/ahdpack/ahd_lightmap.gd")


func _viewport(cfg: Dictionary, aabb: AABB) -> SubViewport:
	var vp := SubViewport.new()
	vp.own_world_3d = true
	vp.render_target_update_mode = SubViewport.UPDATE_ALWAYS
	vp.size = Vector2i(int(cfg["width"]), int(cfg["height"]))
	add_child(vp)
	var we := WorldEnvironment.new()
	var env := Environment.new()
	env.background_mode = Environment.BG_COLOR
	env.background_color = Color(0, 0, 0)
	env.ambient_light_source = Environment.AMBIENT_SOURCE_DISABLED
	env.reflected_light_source = Environment.REFLECTION_SOURCE_DISABLED
	env.tonemap_mode = Environment.TONE_MAPPER_LINEAR
	env.tonemap_exposure = float(cfg["exposure"])
	we.environment = env
	vp.add_child(we)
	# three's scene page's framing (docs/examples/three/scene.html, frameCamera).
	var cam := Camera3D.new()
	cam.fov = 50.0
	cam.keep_aspect = Camera3D.KEEP_HEIGHT
	var c := aabb.get_center()
	var r := aabb.size.length() * 0.5
	var d := Vector3(0.3, 1.0, 0.45).normalized()
	cam.near = r * 0.01
	cam.far = r * 10.0
	vp.add_child(cam)
	cam.look_at_from_position(c + d * (r / sin(deg_to_rad(25.0)) * 0.7), c)
	cam.current = true
	return vp


# glTF node i is manifest instance i (depth first, as the glTF lists them).
func _meshes(root: Node) -> Array:
	return root.find_children("*", "MeshInstance3D", true, false)


func _ready() -> void:
	var cfg = JSON.parse_string(FileAccess.get_file_as_string("res://native.json"))
	var lm := AhdLightmapScript.new()
	if lm.open("res://conv/world.json") != OK:
		H.fail(lm.error)
		return
	var instances: Array = lm.manifest.get("instances", [])
	var doc := GLTFDocument.new()
	var state := GLTFState.new()
	var err := doc.append_from_buffer(FileAccess.get_file_as_bytes("res://conv/world.glb"), "", state)
	if err != OK:
		H.fail("glTF: " + error_string(err))
		return

	# The source SH as Godot's LightmapGI takes it.
	var w := int(cfg["sh_width"])
	var lh := int(cfg["sh_layer_height"])
	var nl := int(cfg["sh_layers"])
	var bytes := FileAccess.get_file_as_bytes("res://native.bin")
	if bytes.size() != w * lh * nl * 12:
		H.fail("native.bin: %d bytes, expected %d" % [bytes.size(), w * lh * nl * 12])
		return
	var stack := Image.create_from_data(w, lh * nl, false, Image.FORMAT_RGBF, bytes)
	stack.convert(Image.FORMAT_RGBH)
	var layers: Array[Image] = []
	for i in nl:
		layers.append(stack.get_region(Rect2i(0, i * lh, w, lh)))
	var sh_tex := Texture2DArray.new()
	if sh_tex.create_from_images(layers) != OK:
		H.fail("Texture2DArray.create_from_images failed for the SH layers")
		return

	# Native: LightmapGI.
	var native_root := doc.generate_scene(state)
	var aabb := AABB()
	var first := true
	for mi in _meshes(native_root):
		var b: AABB = mi.transform * mi.get_aabb()
		aabb = b if first else aabb.merge(b)
		first = false
	var vp_native := _viewport(cfg, aabb)
	vp_native.add_child(native_root)
	var native_mat := StandardMaterial3D.new()
	native_mat.albedo_color = Color(1, 1, 1)
	native_mat.roughness = 1.0
	native_mat.metallic = 0.0
	native_mat.specular_mode = BaseMaterial3D.SPECULAR_DISABLED
	var data := LightmapGIData.new()
	data.set_lightmap_textures([sh_tex])
	data.set_uses_spherical_harmonics(true)
	data.call("_set_uses_packed_directional", true)
	var sh := PackedColorArray()
	sh.resize(9)
	data.call("_set_probe_data", {
		"bounds": aabb.grow(1.0), "points": PackedVector3Array([aabb.get_center()]), "sh": sh,
		"tetrahedra": PackedInt32Array(), "bsp": PackedInt32Array(), "interior": false,
		"baked_exposure": 1.0, "lightprobe_hash": 0,
	})
	var lmgi := LightmapGI.new()
	vp_native.add_child(lmgi)
	var n := 0
	for mi in _meshes(native_root):
		if n >= instances.size():
			H.fail("the glTF has more meshes than the manifest has instances")
			return
		mi.material_override = native_mat
		mi.gi_mode = GeometryInstance3D.GI_MODE_STATIC
		data.add_user(lmgi.get_path_to(mi), Rect2(0, 0, 1, 1), int(instances[n]["page"]), -1)
		n += 1
	if n == 0:
		H.fail("the glTF has no meshes")
		return
	lmgi.light_data = data

	# The add-on: the same meshes, its shader at the same rectangle and page, LightmapGI off.
	var addon_root := native_root.duplicate()
	var vp_addon := _viewport(cfg, aabb)
	vp_addon.add_child(addon_root)
	var k := 0
	for mi in _meshes(addon_root):
		mi.material_override = lm.make_material(Rect2(0, 0, 1, 1), int(instances[k]["page"]))
		mi.gi_mode = GeometryInstance3D.GI_MODE_DISABLED
		k += 1

	for i in 4:
		await RenderingServer.frame_post_draw
	var a := vp_native.get_texture().get_image()
	var b := vp_addon.get_texture().get_image()
	H.emit_file("native.png", a.save_png_to_buffer())
	H.emit_file("addon.png", b.save_png_to_buffer())
	H.emit_json("report.json", {"meshes": n, "users": data.get_user_count(), "sh_layers": sh_tex.get_layers(),
		"sh_format": sh_tex.get_format(), "width": a.get_width(), "height": a.get_height()})
	H.done(0)
