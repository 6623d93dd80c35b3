# Copied into every project that run_godot.mjs packs (as res://harness.gd). Hands files back to the
# page that booted Godot (tests/tools/godot/boot.js) through JavaScriptBridge.eval, base64 for bytes.
#   const H = preload("res://harness.gd")
#   H.emit_json("x.json", value); H.emit_file("x.res", bytes); H.emit_path("user://x.tres"); H.done(self)
extends RefCounted


static func emit_file(name: String, bytes: PackedByteArray) -> void:
	JavaScriptBridge.eval("window.__ahd.emit(%s, '%s')" % [JSON.stringify(name), Marshalls.raw_to_base64(bytes)])


static func emit_text(name: String, text: String) -> void:
	emit_file(name, text.to_utf8_buffer())


# Keys sorted, floats at full precision (a float32 value read back as double prints exactly).
static func emit_json(name: String, value: Variant) -> void:
	emit_text(name, JSON.stringify(value, "", true, true) + "\n")


# Emits a file Godot wrote (user://...), under its file name or `name`.
static func emit_path(path: String, name: String = "") -> void:
	if not FileAccess.file_exists(path):
		fail("missing " + path)
		return
	var bytes := FileAccess.get_file_as_bytes(path)
	emit_file(name if name != "" else path.get_file(), bytes)


# PackedScene.pack(root), with the nodes' unique_id (Godot 4.6 draws them at random for every
# pack; they are written as `unique_id=` in a .tscn) set to 1, 2, ... in node order, so that a
# saved scene is the same at every run. null (after fail()) when pack fails.
static func pack_scene(root: Node) -> PackedScene:
	var scene := PackedScene.new()
	var err := scene.pack(root)
	if err != OK:
		fail("PackedScene.pack: error %d" % err)
		return null
	var bundle: Dictionary = scene._get_bundled_scene()
	if bundle.has("node_ids"):
		var ids := PackedInt32Array()
		for i in bundle["node_ids"].size():
			ids.append(i + 1)
		bundle["node_ids"] = ids
		scene._set_bundled_scene(bundle)
	return scene


# Tells the page the project is done; code != 0 marks a failure.
static func done(code: int = 0) -> void:
	JavaScriptBridge.eval("window.__ahd.done(%d)" % code)


static func fail(message: String) -> void:
	printerr("harness: FAIL: " + message)
	done(1)
