# What Godot's FBX importer (FBXDocument, ufbx) builds from each FBX file packed beside this
# script: fbx.json {file: {"err", "nodes": [{"class", "name", "transform", "surfaces"}]}}.
extends Node

const H = preload("res://harness.gd")
const J = preload("res://mesh_json.gd")
const FILES := ["res://room.fbx", "res://room_zup.fbx", "res://quads.fbx"]


func _walk(n: Node, out: Array) -> void:
	var m = null
	if n is MeshInstance3D:
		m = n.mesh
	out.append({"name": String(n.name), "class": n.get_class(),
		"transform": J.to_json(n.transform) if n is Node3D else null,
		"surfaces": J.surfaces(m, [Mesh.ARRAY_VERTEX, Mesh.ARRAY_NORMAL, Mesh.ARRAY_INDEX]) if m != null else []})
	for c in n.get_children():
		_walk(c, out)


func _ready() -> void:
	if not ClassDB.class_exists("FBXDocument"):
		H.fail("no FBXDocument in this build")
		return
	var out := {}
	for f in FILES:
		if not FileAccess.file_exists(f):
			continue
		var doc = ClassDB.instantiate("FBXDocument")
		var state = ClassDB.instantiate("FBXState")
		var err = doc.append_from_file(f, state)
		var entry := {"err": err}
		if err == OK:
			var nodes := []
			_walk(doc.generate_scene(state), nodes)
			entry["nodes"] = nodes
		out[f.get_file()] = entry
	H.emit_json("fbx.json", out)
	H.done(0)
