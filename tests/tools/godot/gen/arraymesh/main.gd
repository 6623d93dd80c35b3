# Emits ArrayMesh resources as Godot 4.6 saves them (arraymesh_<name>.tres text, .res and .mesh
# binary; arraymesh_scene.tscn holding mesh "tangents" inline as a sub_resource) and
# arraymesh.json: the arrays Godot gets back when it loads each of those files.
extends Node

const H = preload("res://harness.gd")
const J = preload("res://mesh_json.gd")

const ALL := [Mesh.ARRAY_VERTEX, Mesh.ARRAY_NORMAL, Mesh.ARRAY_TANGENT, Mesh.ARRAY_TEX_UV, Mesh.ARRAY_TEX_UV2, Mesh.ARRAY_INDEX]


func _ready() -> void:
	var meshes := {
		"tangents": _grid_mesh(true, true, Vector3(0.0, 0.0, 0.0)),
		"no_tangents": _two_surfaces(),
		"no_index": _grid_mesh(false, false, Vector3(0.25, -0.5, 2.0)),
	}
	meshes["tangents"].lightmap_size_hint = Vector2i(32, 16)
	var report := []
	for name in meshes:
		var mesh: ArrayMesh = meshes[name]
		for ext in ["tres", "res", "mesh"]:
			var file := "arraymesh_%s.%s" % [name, ext]
			if not _save_and_report(mesh, file, report):
				return
	# One mesh inline in a scene.
	var root := Node3D.new()
	root.name = "Scene"
	var mi := MeshInstance3D.new()
	mi.name = "Mesh"
	var inline: ArrayMesh = meshes["tangents"].duplicate()
	inline.resource_scene_unique_id = "ArrayMesh_tangents"
	mi.mesh = inline
	root.add_child(mi)
	mi.owner = root
	var scene := H.pack_scene(root)
	if scene == null:
		return
	if ResourceSaver.save(scene, "user://arraymesh_scene.tscn") != OK:
		H.fail("save arraymesh_scene.tscn")
		return
	H.emit_path("user://arraymesh_scene.tscn")
	var loaded: PackedScene = ResourceLoader.load("user://arraymesh_scene.tscn", "", ResourceLoader.CACHE_MODE_IGNORE)
	var node := loaded.instantiate()
	report.append(_describe("arraymesh_scene.tscn", node.get_node("Mesh").mesh))
	node.free()
	H.emit_json("arraymesh.json", report)
	H.done(0)


func _save_and_report(mesh: ArrayMesh, file: String, report: Array) -> bool:
	var path := "user://" + file
	var err := ResourceSaver.save(mesh, path)
	if err != OK:
		H.fail("%s: save: error %d" % [file, err])
		return false
	H.emit_path(path)
	var back = ResourceLoader.load(path, "", ResourceLoader.CACHE_MODE_IGNORE)
	# A release build skips GDScript's runtime checks: check what matters by hand.
	if not (back is ArrayMesh) or back.get_surface_count() != mesh.get_surface_count() \
			or back.surface_get_arrays(0)[Mesh.ARRAY_VERTEX] != mesh.surface_get_arrays(0)[Mesh.ARRAY_VERTEX]:
		H.fail("%s: load back failed" % file)
		return false
	report.append(_describe(file, back))
	return true


func _describe(file: String, mesh: ArrayMesh) -> Dictionary:
	var surfaces := J.surfaces(mesh, ALL)
	for s in mesh.get_surface_count():
		surfaces[s]["format"] = mesh.surface_get_format(s)
		surfaces[s]["primitive"] = mesh.surface_get_primitive_type(s)
	var hint := mesh.lightmap_size_hint
	return {"file": file, "type": mesh.get_class(), "lightmap_size_hint": [hint.x, hint.y], "surfaces": surfaces}


# A 3 x 2 grid of quads on a tilted, bent sheet; indexed or as a plain triangle list.
func _grid_mesh(indexed: bool, tangents: bool, offset: Vector3) -> ArrayMesh:
	var nx := 3
	var ny := 2
	var verts := PackedVector3Array()
	var normals := PackedVector3Array()
	var tans := PackedFloat32Array()
	var uvs := PackedVector2Array()
	var uv2s := PackedVector2Array()
	for j in ny + 1:
		for i in nx + 1:
			var u := float(i) / nx
			var v := float(j) / ny
			var z := 0.3 * sin(2.0 * u) * cos(v)
			verts.append(offset + Vector3(1.5 * u - 0.7, 0.9 * v + 0.1 * u, z))
			var n := Vector3(-0.6 * cos(2.0 * u) * cos(v), 0.3 * sin(2.0 * u) * sin(v), 1.0).normalized()
			normals.append(n)
			var t := Vector3(1.0, 0.0, 0.6 * cos(2.0 * u)).normalized()
			tans.append_array([t.x, t.y, t.z, 1.0 if i % 2 == 0 else -1.0])
			uvs.append(Vector2(u, 1.0 - v))
			uv2s.append(Vector2(0.03125 + 0.4375 * u, 0.5625 + 0.40625 * v))
	var idx := PackedInt32Array()
	for j in ny:
		for i in nx:
			var a := j * (nx + 1) + i
			idx.append_array([a, a + 1, a + nx + 1, a + 1, a + nx + 2, a + nx + 1])
	if not indexed:  # the plain triangle list: each index's vertex written out
		var fv := PackedVector3Array()
		var fn := PackedVector3Array()
		var ft := PackedFloat32Array()
		var fu := PackedVector2Array()
		var fu2 := PackedVector2Array()
		for k in idx:
			fv.append(verts[k])
			fn.append(normals[k])
			ft.append_array(tans.slice(k * 4, k * 4 + 4))
			fu.append(uvs[k])
			fu2.append(uv2s[k])
		verts = fv
		normals = fn
		tans = ft
		uvs = fu
		uv2s = fu2
	var arrays := []
	arrays.resize(Mesh.ARRAY_MAX)
	arrays[Mesh.ARRAY_VERTEX] = verts
	arrays[Mesh.ARRAY_NORMAL] = normals
	if tangents:
		arrays[Mesh.ARRAY_TANGENT] = tans
	arrays[Mesh.ARRAY_TEX_UV] = uvs
	arrays[Mesh.ARRAY_TEX_UV2] = uv2s
	if indexed:
		arrays[Mesh.ARRAY_INDEX] = idx
	var mesh := ArrayMesh.new()
	mesh.add_surface_from_arrays(Mesh.PRIMITIVE_TRIANGLES, arrays)
	return mesh


# Two indexed surfaces, no tangents: the grid and a second, smaller one moved up.
func _two_surfaces() -> ArrayMesh:
	var mesh := ArrayMesh.new()
	for m in [_grid_mesh(true, false, Vector3(0, 0, 0)), _grid_mesh(true, false, Vector3(0.0, 2.0, -0.125))]:
		mesh.add_surface_from_arrays(Mesh.PRIMITIVE_TRIANGLES, m.surface_get_arrays(0))
	return mesh
