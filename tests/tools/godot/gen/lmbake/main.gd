# Emits lightmap data files that Godot 4.6 writes (lmbake_*.lmbake: LightmapGIData saved by
# ResourceSaver, binary) and lmbake.json: what Godot reports after loading each of them back, and
# after loading every real .lmbake that generate.sh packs under res://real/.
extends Node

const H = preload("res://harness.gd")
const J = preload("res://mesh_json.gd")

# name -> [layers, width, height, uses_spherical_harmonics, packed_directional, users], a user
# being [path, uv_scale, slice_index, sub_instance].
var CASES := {
	"lmbake_1slice": [1, 8, 8, false, false, [
		["Floor", Rect2(0.0, 0.0, 1.0, 0.5), 0, -1],
		["Props/Chair", Rect2(0.0, 0.5, 0.5, 0.5), 0, -1],
		["Props/Grass", Rect2(0.5, 0.5, 0.25, 0.25), 0, 0],
		["Props/Grass", Rect2(0.75, 0.5, 0.25, 0.25), 0, 3],
	]],
	"lmbake_4slices_sh": [4, 4, 4, true, false, [
		["World/Walls", Rect2(0.0, 0.0, 1.0, 1.0), 0, -1],
		["World/Floor", Rect2(0.0, 0.0, 0.75, 0.75), 1, -1],
		["World/Props/Table", Rect2(0.75, 0.0, 0.25, 0.125), 1, -1],
		["../Outside/Tree", Rect2(0.0, 0.0, 0.5, 1.0), 2, -1],
		["World/Props/Lamp", Rect2(0.5, 0.0, 0.3333333, 0.6666667), 2, -1],
		["World/Ceiling", Rect2(0.0, 0.0, 1.0, 1.0), 3, -1],
	]],
	"lmbake_4slices_packed": [4, 4, 4, true, true, [
		["A", Rect2(0.0, 0.0, 1.0, 1.0), 3, -1],
		["B", Rect2(0.1, 0.2, 0.3, 0.4), 2, -1],
		["C", Rect2(0.0, 0.0, 0.5, 0.5), 1, 7],
		["D", Rect2(0.5, 0.5, 0.5, 0.5), 0, -1],
	]],
}


# Four probes (one tetrahedron), 9 SH colours each.
var PROBES := {
	"bounds": AABB(Vector3(-1, 0, -1), Vector3(2, 2, 2)),
	"points": PackedVector3Array([Vector3(-1, 0, -1), Vector3(1, 0, -1), Vector3(0, 0, 1), Vector3(0, 2, 0)]),
	"tetrahedra": PackedInt32Array([0, 1, 2, 3]),
	"bsp": PackedInt32Array(),
	"sh": _sh(4),
	"interior": true,
	"baked_exposure": 0.5,
	"lightprobe_hash": 1234567,
}


static func _sh(n: int) -> PackedColorArray:
	var out := PackedColorArray()
	for i in n * 9:
		out.append(Color(0.125 * (i % 9), 0.25, 1.0 / (1 + i), 1.0))
	return out


func _ready() -> void:
	var report := []
	for name in CASES:
		var c: Array = CASES[name]
		var data := LightmapGIData.new()
		var images: Array[Image] = []
		for layer in c[0]:
			var img := Image.create_empty(c[1], c[2], false, Image.FORMAT_RGBAH)
			img.fill(Color(0.25 * layer, 0.5, 1.0, 1.0))
			images.append(img)
		var tex := Texture2DArray.new()
		var err := tex.create_from_images(images)
		if err != OK:
			H.fail("%s: Texture2DArray: error %d" % [name, err])
			return
		data.lightmap_textures = [tex]
		data.uses_spherical_harmonics = c[3]
		data._set_uses_packed_directional(c[4])
		for u in c[5]:
			data.add_user(NodePath(u[0]), u[1], u[2], u[3])
		if name == "lmbake_4slices_sh":
			data.set("probe_data", PROBES)
		var path := "user://%s.lmbake" % name
		err = ResourceSaver.save(data, path)
		if err != OK:
			H.fail("%s: save: error %d" % [name, err])
			return
		H.emit_path(path)
		var back = ResourceLoader.load(path, "", ResourceLoader.CACHE_MODE_IGNORE)
		if back == null:
			H.fail("%s: load back failed" % name)
			return
		# A release build skips GDScript's runtime checks: check what matters by hand.
		if back.get_user_count() != c[5].size() or back.lightmap_textures.size() != 1:
			H.fail("%s: read back %d users" % [name, back.get_user_count()])
			return
		report.append(_describe(name + ".lmbake", back))
	# The real bakes (tests/data/**/*.lmbake); their textures are not in the pack (Godot would need
	# its importer's .ctexarray), so missing dependencies must not abort the load.
	ResourceLoader.set_abort_on_missing_resources(false)
	for path in _find("res://real", "lmbake"):
		var data = ResourceLoader.load(path, "", ResourceLoader.CACHE_MODE_IGNORE)
		if data == null:
			H.fail("%s: load failed" % path)
			return
		var entry := _describe(path.trim_prefix("res://real/"), data)
		entry["dependencies"] = Array(ResourceLoader.get_dependencies(path))
		report.append(entry)
	H.emit_json("lmbake.json", report)
	H.done(0)


func _describe(file: String, data: LightmapGIData) -> Dictionary:
	var users := []
	var raw: Array = data.get("user_data")
	for i in data.get_user_count():
		users.append({
			"path": String(data.get_user_path(i)),
			"uv_scale": J.to_json(raw[i * 4 + 1]),
			"slice_index": raw[i * 4 + 2],
			"sub_instance": raw[i * 4 + 3],
		})
	var textures := []
	for t in data.lightmap_textures:
		if t == null:
			textures.append(null)
			continue
		textures.append({
			"class": t.get_class(),
			"path": t.resource_path if not t.resource_path.contains("::") else "",
			"layers": t.get_layers(),
			"width": t.get_width(),
			"height": t.get_height(),
			"format": t.get_format(),
		})
	var probe: Dictionary = data.get("probe_data")
	var points: PackedVector3Array = probe.get("points", PackedVector3Array())
	return {
		"file": file,
		"user_count": data.get_user_count(),
		"users": users,
		"uses_spherical_harmonics": data.is_using_spherical_harmonics(),
		"uses_packed_directional": data._is_using_packed_directional(),
		"lightmap_textures": textures,
		"probe": {
			"count": points.size(),
			# Every point of a small set; the first 4 of a large one.
			"points": J.to_json(points if points.size() <= 16 else points.slice(0, 4)),
			"bounds": J.to_json(probe.get("bounds", AABB())),
			"lightprobe_hash": probe.get("lightprobe_hash", 0),
			"tetrahedra": probe.get("tetrahedra", PackedInt32Array()).size() / 4,
			"interior": probe.get("interior", false),
			"baked_exposure": probe.get("baked_exposure", 0.0),
		},
	}


func _find(dir: String, ext: String) -> Array:
	var out := []
	var d := DirAccess.open(dir)
	if d == null:
		return out
	for f in d.get_files():
		if f.get_extension() == ext:
			out.append(dir.path_join(f))
	for sub in d.get_directories():
		out.append_array(_find(dir.path_join(sub), ext))
	out.sort()
	return out
