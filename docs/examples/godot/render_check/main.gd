# Renders a quad lit by the ahdpack add-on (res://addons/ahdpack) in Godot 4 and hands the pixels
# back; GodotAddon.* (tests/judges/godot_addon_test.cpp) packs this project with the add-on, ahdpack's
# planes and res://check.json, runs it with tests/tools/godot/run_godot.mjs and compares every pixel
# with ahdpack's reference decoder. docs/engine-integration.md "Godot 4 (tested)".
#
# The Compatibility renderer hands back 8 bits per channel, clamped to [0,1], through an sRGB encode
# and decode that do not cancel at the low end (k/255 for k = 0..7 comes back 0; a float viewport,
# use_hdr_2d, comes back clamped and 8-bit as well). So the shader's test hook (AHD_READBACK) writes
# each channel's float32 bits 7 at a time as (digit + 8)/255 (five renders per image), and a
# calibration ramp (every k/255, rendered the same way) lets the test map the bytes back exactly.
extends Node

const H = preload("res://harness.gd")
const AhdLightmapScript = preload("res://addons/ahdpack/ahd_lightmap.gd")

var vp: SubViewport
var cam: Camera3D
var quad: MeshInstance3D
var WORLD_TURN := Basis.from_euler(Vector3(0.6, -0.9, 0.35))


func _ready() -> void:
	var cfg = JSON.parse_string(FileAccess.get_file_as_string("res://check.json"))
	if typeof(cfg) != TYPE_DICTIONARY:
		H.fail("res://check.json missing")
		return
	_make_viewport()
	var report := {"runs": [], "bptc": RenderingServer.has_os_feature("bptc"),
		"rgtc": RenderingServer.has_os_feature("rgtc")}
	await _calibrate()
	# The add-on's shader with its readback hook switched on.
	var code: String = load(AhdLightmapScript.SHADER_PATH).code
	var readback := Shader.new()
	readback.code = code.replace("shader_type spatial;\n", "shader_type spatial;\n#define AHD_READBACK\n")
	for run in cfg["runs"]:
		var lm := AhdLightmapScript.new()
		if lm.open(run["manifest"]) != OK:
			H.fail(lm.error)
			return
		var w := int(lm.manifest["width"])
		var h := int(lm.manifest["height"])
		var normal := _detail_normal_map(w, h)
		var id: String = run["id"]
		H.emit_file(id + ".normal.bin", normal.get_data())
		var formats := {}
		for k in lm.image_formats:
			formats[k] = lm.image_formats[k]
		var entry := {"id": id, "width": w, "height": h, "layers": lm.layers, "formats": formats, "dir_in_ra": lm.dir_in_ra,
			"iz_mips": lm.iz.get_layer_data(0).get_mipmap_count(), "cases": []}
		# [name, viewport size, atlas rect, normal map, page]
		var cases := [
			["flat", Vector2i(w, h), Rect2(0, 0, 1, 1), false, 0],
			["detail", Vector2i(w, h), Rect2(0, 0, 1, 1), true, 0],
			["rect", Vector2i(w / 2, h / 2), Rect2(0.25, 0.5, 0.5, 0.5), false, 0],
			["level1", Vector2i(w / 2, h / 2), Rect2(0, 0, 1, 1), false, 0],
			# The world-space path (direction_frame "normal-frame"): the quad and the camera turned
			# together by WORLD_TURN, so the image is the same but the quad's normal is not +z.
			["world", Vector2i(w, h), Rect2(0, 0, 1, 1), true, 0],
		]
		if lm.layers > 1:  # an atlas: each page, at the normal map's normal in the stored frame
			cases = []
			for page in lm.layers:
				cases.append(["page%d" % page, Vector2i(w, h), Rect2(0, 0, 1, 1), true, page])
		# The dir and ratio planes as the shader samples them (x, y, ratio), not decoded, per page.
		for page in lm.layers:
			cases.append(["planes%d" % page, Vector2i(w, h), Rect2(0, 0, 1, 1), false, page])
		for c in cases:
			var mat := lm.make_material(c[2], c[4], readback)
			var world: bool = c[0] == "world"
			mat.set_shader_parameter("ahd_world_frame", world)
			_turn(WORLD_TURN if world else Basis.IDENTITY)
			mat.set_shader_parameter("use_normal_map", c[3])
			mat.set_shader_parameter("ahd_readback_planes", c[0].begins_with("planes"))
			mat.set_shader_parameter("normal_texture", ImageTexture.create_from_image(normal))
			var bytes := PackedByteArray()
			var fmt := -1
			for b in 5:
				mat.set_shader_parameter("ahd_readback_digit", b)
				var img := await _render(c[1], mat)
				fmt = img.get_format()
				bytes.append_array(img.get_data())
			H.emit_file("%s.%s.bin" % [id, c[0]], bytes)
			entry["cases"].append({"name": c[0], "width": c[1].x, "height": c[1].y, "rect": [c[2].position.x, c[2].position.y, c[2].size.x, c[2].size.y],
				"normal_map": c[3], "page": c[4], "image_format": fmt, "bytes": bytes.size(), "world_frame": world})
		_turn(Basis.IDENTITY)
		report["runs"].append(entry)
	var t := WORLD_TURN
	report["world_turn"] = [t.x.x, t.x.y, t.x.z, t.y.x, t.y.y, t.y.z, t.z.x, t.z.y, t.z.z]  # columns
	report["instance"] = _instance_check(cfg["runs"][0]["manifest"])
	report["lit"] = await _lit_check(cfg["runs"][0]["manifest"])
	H.emit_json("report.json", report)
	H.done(0)


# The scene-side path: ahd_lightmap_instance.gd on a MeshInstance3D, as a scene would hold it.
func _instance_check(manifest: String) -> Dictionary:
	var mi := MeshInstance3D.new()
	mi.mesh = quad.mesh
	mi.set_script(load("res://addons/ahdpack/ahd_lightmap_instance.gd"))
	mi.set("manifest", manifest)
	mi.set("atlas_rect", Rect2(0.25, 0.5, 0.5, 0.25))
	mi.set("page", 0)
	mi.set("albedo", Color(0.5, 0.25, 1.0))
	add_child(mi)  # _ready applies the lightmap
	var mat := mi.material_override as ShaderMaterial
	if mat == null:
		return {"material": false}
	var r: Vector4 = mat.get_shader_parameter("ahd_uv_rect")
	var a: Color = mat.get_shader_parameter("albedo")
	return {"material": true, "gi_mode": mi.gi_mode, "gi_mode_disabled": GeometryInstance3D.GI_MODE_DISABLED,
		"rect": [r.x, r.y, r.z, r.w], "page": mat.get_shader_parameter("ahd_page"),
		"dz_min": mat.get_shader_parameter("ahd_dz_min"), "albedo": [a.r, a.g, a.b],
		"shader": mat.shader.resource_path}


# The add-on's shader as a game renders it (no readback hook): ahd_lightmap_instance.gd on the quad,
# full atlas, albedo (1, 0.5, 1), in an environment without
# ambient light, reflections or tone mapping, so the image is the add-on's emission, linear albedo
# E / π (the shader writes it for the Compatibility renderer's sRGB decode), 8 bits.
func _lit_check(manifest: String) -> Dictionary:
	var we := WorldEnvironment.new()
	var env := Environment.new()
	env.background_mode = Environment.BG_COLOR
	env.background_color = Color(0, 0, 0)
	env.ambient_light_source = Environment.AMBIENT_SOURCE_COLOR
	env.ambient_light_color = Color(0, 0, 0)
	env.ambient_light_energy = 0.0
	env.reflected_light_source = Environment.REFLECTION_SOURCE_DISABLED
	env.tonemap_mode = Environment.TONE_MAPPER_LINEAR
	we.environment = env
	vp.add_child(we)
	var mi := MeshInstance3D.new()
	mi.mesh = quad.mesh
	mi.set_script(load("res://addons/ahdpack/ahd_lightmap_instance.gd"))
	mi.set("manifest", manifest)
	mi.set("albedo", Color(1.0, 0.5, 1.0))
	quad.visible = false
	vp.add_child(mi)
	var m: Dictionary = mi.get("_loaded")[manifest].manifest
	var size := Vector2i(int(m["width"]), int(m["height"]))
	vp.size = size
	await RenderingServer.frame_post_draw
	await RenderingServer.frame_post_draw
	var img := vp.get_texture().get_image()
	H.emit_file("lit.bin", img.get_data())
	vp.remove_child(mi)
	vp.remove_child(we)
	quad.visible = true
	return {"width": size.x, "height": size.y, "image_format": img.get_format(), "albedo": [1.0, 0.5, 1.0]}


func _make_viewport() -> void:
	vp = SubViewport.new()
	vp.own_world_3d = true
	vp.render_target_update_mode = SubViewport.UPDATE_ALWAYS
	add_child(vp)
	cam = Camera3D.new()
	cam.projection = Camera3D.PROJECTION_ORTHOGONAL
	cam.size = 2.0
	cam.keep_aspect = Camera3D.KEEP_HEIGHT
	cam.near = 0.05
	cam.far = 10.0
	cam.position = Vector3(0, 0, 1)
	vp.add_child(cam)
	cam.current = true
	quad = MeshInstance3D.new()
	quad.mesh = _quad_mesh()
	vp.add_child(quad)


# A 2x2 quad filling the square view: normal +z, tangent +x, UV = UV2 = (0,0) top left.
func _quad_mesh() -> ArrayMesh:
	var arrays := []
	arrays.resize(Mesh.ARRAY_MAX)
	var pos := PackedVector3Array([Vector3(-1, 1, 0), Vector3(1, 1, 0), Vector3(1, -1, 0), Vector3(-1, -1, 0)])
	var uv := PackedVector2Array([Vector2(0, 0), Vector2(1, 0), Vector2(1, 1), Vector2(0, 1)])
	var nrm := PackedVector3Array()
	var tan := PackedFloat32Array()
	for i in 4:
		nrm.append(Vector3(0, 0, 1))
		tan.append_array([1.0, 0.0, 0.0, 1.0])
	arrays[Mesh.ARRAY_VERTEX] = pos
	arrays[Mesh.ARRAY_NORMAL] = nrm
	arrays[Mesh.ARRAY_TANGENT] = tan
	arrays[Mesh.ARRAY_TEX_UV] = uv
	arrays[Mesh.ARRAY_TEX_UV2] = uv
	arrays[Mesh.ARRAY_INDEX] = PackedInt32Array([0, 1, 2, 0, 2, 3])  # clockwise: Godot's front face
	var m := ArrayMesh.new()
	m.add_surface_from_arrays(Mesh.PRIMITIVE_TRIANGLES, arrays)
	return m


# Turns the quad and the camera by `b` about the origin (the camera stays on the quad's normal).
func _turn(b: Basis) -> void:
	quad.transform = Transform3D(b, Vector3.ZERO)
	cam.transform = Transform3D(b, b * Vector3(0, 0, 1))


func _render(size: Vector2i, mat: Material) -> Image:
	vp.size = size
	quad.material_override = mat
	await RenderingServer.frame_post_draw
	await RenderingServer.frame_post_draw
	return vp.get_texture().get_image()


# A tangent-space normal map (RGBA8, 0.5 + 0.5 n) of the detail normal the three.js check uses.
func _detail_normal_map(w: int, h: int) -> Image:
	var data := PackedByteArray()
	for y in h:
		for x in w:
			var u := (x + 0.5) / w
			var v := (y + 0.5) / h
			var n := Vector3(0.6 * sin(TAU * 3.0 * u), 0.6 * cos(TAU * 2.0 * v), 1.0).normalized()
			for c in [n.x, n.y, n.z]:
				data.append(clampi(roundi((c * 0.5 + 0.5) * 255.0), 0, 255))
			data.append(255)
	return Image.create_from_data(w, h, false, Image.FORMAT_RGBA8, data)


# Every byte value k (a 16x16 ramp, k = 16 row + column) written as k/255 by an unshaded shader as
# the hook writes its digits: what comes back is Godot's output transfer, which the test inverts.
func _calibrate() -> void:
	var mat := ShaderMaterial.new()
	mat.shader = Shader.new()
	mat.shader.code = "shader_type spatial;\nrender_mode unshaded;\nvoid fragment() {\n" + \
		"  vec2 p = floor(UV * 16.0);\n  ALBEDO = vec3((p.y * 16.0 + p.x) / 255.0);\n}\n"
	var img := await _render(Vector2i(16, 16), mat)
	H.emit_file("ramp.bin", img.get_data())
	if img.get_format() != Image.FORMAT_RGBA8:
		H.fail("the viewport image is format %d, not RGBA8" % img.get_format())
