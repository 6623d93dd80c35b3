# Emits primitives.json (the arrays Godot 4.6 builds for each PrimitiveMesh type with add_uv2 on,
# over several parameter sets) and primitives.tscn (a scene holding every one of those meshes, as
# Godot's ResourceSaver writes it).
extends Node

const H = preload("res://harness.gd")
const Mesh3 = preload("res://mesh_json.gd")

# type -> list of parameter sets (property -> value); add_uv2 = true is set on all of them.
const SETS := {
	"BoxMesh": [
		{},
		{"size": Vector3(2.0, 0.5, 1.5), "subdivide_width": 2, "subdivide_height": 1, "subdivide_depth": 3},
		{"size": Vector3(1.0, 3.0, 1.0), "uv2_padding": 8.0},
	],
	"PlaneMesh": [
		{},
		{"orientation": PlaneMesh.FACE_X, "size": Vector2(3.0, 1.5), "subdivide_width": 2, "subdivide_depth": 3},
		{"orientation": PlaneMesh.FACE_Z, "center_offset": Vector3(0.5, 0.0, -1.0), "uv2_padding": 5.0},
		{"orientation": PlaneMesh.FACE_Y, "size": Vector2(0.7, 4.0), "subdivide_depth": 1, "uv2_padding": 0.5},
	],
	"QuadMesh": [
		{},
		{"orientation": PlaneMesh.FACE_Y, "size": Vector2(2.0, 3.0), "subdivide_width": 1, "subdivide_depth": 2},
		{"orientation": PlaneMesh.FACE_X, "uv2_padding": 6.0},
	],
	"PrismMesh": [
		{},
		{"left_to_right": 0.0, "size": Vector3(2.0, 1.0, 0.5)},
		{"left_to_right": 1.0, "subdivide_width": 2, "subdivide_height": 1, "subdivide_depth": 2},
		{"left_to_right": 0.3, "uv2_padding": 4.0},
	],
	"CylinderMesh": [
		{},
		{"cap_top": false, "top_radius": 0.25, "radial_segments": 12, "rings": 2},
		{"cap_bottom": false, "bottom_radius": 0.0, "height": 3.0, "radial_segments": 10, "rings": 0},
		{"uv2_padding": 6.0, "radial_segments": 8, "rings": 1},
	],
	"CapsuleMesh": [
		{},
		{"radius": 0.25, "height": 1.5, "radial_segments": 16, "rings": 3},
		{"uv2_padding": 0.0, "radial_segments": 8, "rings": 1},
	],
	"SphereMesh": [
		{},
		{"is_hemisphere": true, "radial_segments": 16, "rings": 8},
		{"radius": 1.0, "height": 1.5, "radial_segments": 12, "rings": 6, "uv2_padding": 3.0},
	],
	"TorusMesh": [
		{},
		{"inner_radius": 0.25, "outer_radius": 1.5, "rings": 16, "ring_segments": 8},
		{"uv2_padding": 1.0, "rings": 12, "ring_segments": 6},
	],
}

# Properties that say nothing about the geometry.
const SKIP := ["material", "custom_aabb", "flip_faces", "script"]


func _ready() -> void:
	var entries := []
	var root := Node3D.new()
	root.name = "Primitives"
	for type in SETS:
		var n := 0
		for props in SETS[type]:
			var mesh: PrimitiveMesh = ClassDB.instantiate(type)
			mesh.add_uv2 = true
			for k in props:
				mesh.set(k, props[k])
			var node_name := "%s_%d" % [type, n]
			# A fixed id, so that the saved scene is the same at every run.
			mesh.resource_scene_unique_id = node_name
			var mi := MeshInstance3D.new()
			mi.name = node_name
			mi.mesh = mesh
			root.add_child(mi)
			mi.owner = root
			var hint := mesh.get_lightmap_size_hint()
			# A release build skips GDScript's runtime checks: check what matters by hand.
			if mesh.surface_get_arrays(0)[Mesh.ARRAY_VERTEX].size() == 0 or hint.x <= 0 or hint.y <= 0:
				H.fail("%s: no arrays or no lightmap size hint" % node_name)
				return
			entries.append({
				"type": type,
				"node": node_name,
				"props": _props(mesh),
				"lightmap_size_hint": [hint.x, hint.y],
				"surfaces": Mesh3.surfaces(mesh),
			})
			n += 1
	var scene := H.pack_scene(root)
	if scene == null:
		return
	var err := OK
	err = ResourceSaver.save(scene, "user://primitives.tscn")
	if err != OK:
		H.fail("save: %d" % err)
		return
	H.emit_json("primitives.json", entries)
	H.emit_path("user://primitives.tscn")
	H.done(0)


func _props(mesh: PrimitiveMesh) -> Dictionary:
	var out := {}
	for p in mesh.get_property_list():
		if not (p.usage & PROPERTY_USAGE_STORAGE) or p.name.begins_with("resource_") or p.name in SKIP:
			continue
		out[p.name] = Mesh3.to_json(mesh.get(p.name))
	return out
