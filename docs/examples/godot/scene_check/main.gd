# Renders the placed scene `ahdpack scene` writes (res://conv/world.glb, loaded at run time with
# GLTFDocument) lit by the ahdpack add-on from the conversion's planes (res://conv/world.json), seen by
# the camera of res://scene.json (the three.js page's: docs/examples/three/scene.html), and hands the
# image back as godot.png. GodotAddonScene.* (tests/judges/godot_addon_scene_test.cpp) compares it with
# three.js's image. glTF node i is manifest instance i; its TEXCOORD_1 (Godot's UV2) is already in
# atlas space, so every material takes the whole atlas as its rectangle, at the instance's page.
extends Node

const H = preload("res://harness.gd")
const AhdLightmapScript = preload("res://addons/ahdpack/ahd_lightmap.gd")


func _ready() -> void:
	var cfg = JSON.parse_string(FileAccess.get_file_as_string("res://scene.json"))
	var lm := AhdLightmapScript.new()
	if lm.open("res://conv/world.json") != OK:
		H.fail(lm.error)
		return
	var doc := GLTFDocument.new()
	var state := GLTFState.new()
	var err := doc.append_from_buffer(FileAccess.get_file_as_bytes("res://conv/world.glb"), "", state)
	if err != OK:
		H.fail("glTF: " + error_string(err))
		return
	var root := doc.generate_scene(state)
	var vp := SubViewport.new()
	vp.own_world_3d = true
	vp.render_target_update_mode = SubViewport.UPDATE_ALWAYS
	vp.size = Vector2i(int(cfg["width"]), int(cfg["height"]))
	add_child(vp)
	var we := WorldEnvironment.new()
	var env := Environment.new()
	env.background_mode = Environment.BG_COLOR
	env.background_color = Color(0, 0, 0)
	env.tonemap_mode = Environment.TONE_MAPPER_LINEAR
	we.environment = env
	vp.add_child(we)
	# The add-on's shader, its output replaced by three's scene page's: unshaded, ACES fit of E x exposure
	# encoded to sRGB as three's page does (Godot's unshaded Compatibility output to a
# SubViewport reads back without an encode of its own).
	var code: String = load(AhdLightmapScript.SHADER_PATH).code
	code = code.replace("shader_type spatial;\n", "shader_type spatial;\nrender_mode unshaded;\nuniform float view_exposure = 1.0;\n")
	code = code.replace("  ALBEDO = base.rgb;\n", "  vec3 x = e * view_exposure;\n  vec3 c = clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);\n  ALBEDO = mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));\n")
	if not code.contains("view_exposure;\n  vec3 c"):
		H.fail("the add-on's shader no longer has the lines this check replaces")
		return
	var shader := Shader.new()
	shader.code = code
	var instances: Array = lm.manifest.get("instances", [])
	var n := 0
	for node in root.get_children():
		if not (node is MeshInstance3D):
			continue
		if n >= instances.size():
			H.fail("the glTF has more meshes than the manifest has instances")
			return
		var mat := lm.make_material(Rect2(0, 0, 1, 1), int(instances[n]["page"]), shader)
		mat.set_shader_parameter("view_exposure", float(cfg["exposure"]))
		node.material_override = mat
		n += 1
	vp.add_child(root)
	var cam := Camera3D.new()
	cam.fov = float(cfg["fov"])
	cam.keep_aspect = Camera3D.KEEP_HEIGHT
	var p = cfg["position"]
	var t = cfg["target"]
	cam.near = float(cfg["near"])
	cam.far = float(cfg["far"])
	vp.add_child(cam)
	cam.look_at_from_position(Vector3(p[0], p[1], p[2]), Vector3(t[0], t[1], t[2]))
	cam.current = true
	for i in 4:
		await RenderingServer.frame_post_draw
	var img := vp.get_texture().get_image()
	H.emit_file("godot.png", img.save_png_to_buffer())
	H.emit_json("report.json", {"meshes": n, "format": img.get_format(), "width": img.get_width(), "height": img.get_height()})
	H.done(0)
