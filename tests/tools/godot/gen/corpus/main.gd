# Writes the files of small Godot projects as Godot 4.6 itself saves them (ResourceSaver): each
# project's scene (.tscn, with primitive meshes and inline ArrayMeshes as sub_resources, external
# .res/.tres ArrayMeshes, an instanced scene), its LightmapGI's .lmbake (LightmapGIData, binary
# format 6, directional + packed L1, every user's atlas rectangle and slice) — and corpus.json: for
# every lightmap user its page, rectangle and the mesh's arrays in world space (positions,
# normals, UV2, indices from surface_get_arrays and the node's global transform), from which
# bake.mjs beside this file writes the lightmap EXR. Emitted names are the project-relative paths
# with "/" spelt "__", prefixed by the project's name.
extends Node

const H = preload("res://harness.gd")
const J = preload("res://mesh_json.gd")

const GAP := 8     # texels between two rectangles of a page (Godot's dilation reaches 4)
const BORDER := 2  # texels from a rectangle to the page's edge


static func _xf(euler_deg: Vector3, scale: Vector3, origin: Vector3) -> Transform3D:
	var b := Basis.from_euler(euler_deg * (PI / 180.0)).scaled_local(scale)
	return Transform3D(b, origin)


# A project: its atlas (size² texels × pages), where its files go, and its nodes:
# [name, kind, mesh type, mesh properties, transform, page]. kind: "prim" (a PrimitiveMesh with
# add_uv2, sub_resource), "inline" (an ArrayMesh built from that primitive's arrays, sub_resource),
# "res" / "tres" (the same saved as an external resource; "tres2" has two surfaces), "prop" (a
# MeshInstance3D named "Lamp" inside an instanced scene res://props/prop.tscn).
func _projects() -> Array:
	return [
		{
			"name": "primitives", "size": 128, "pages": 2, "swapped": [1, 2],
			"scene": "res://scenes/primitives.tscn", "lightmap": "res://lightmaps/primitives",
			"nodes": [
				["Floor", "prim", "PlaneMesh", {"size": Vector2(6.0, 6.0), "subdivide_width": 1}, _xf(Vector3.ZERO, Vector3.ONE, Vector3.ZERO), 0],
				["Box", "prim", "BoxMesh", {"size": Vector3(1.0, 1.5, 0.8)}, _xf(Vector3(0, 30, 0), Vector3.ONE, Vector3(-1.5, 0.75, -1.0)), 0],
				["Wall", "prim", "QuadMesh", {"size": Vector2(4.0, 2.0)}, _xf(Vector3.ZERO, Vector3.ONE, Vector3(0.0, 1.0, -2.9)), 0],
				["Ramp", "prim", "PrismMesh", {"left_to_right": 0.2, "size": Vector3(1.2, 0.8, 1.0)}, _xf(Vector3(0, -20, 0), Vector3.ONE, Vector3(1.6, 0.4, 1.2)), 0],
				["Ball", "prim", "SphereMesh", {"radius": 0.6, "height": 1.2, "radial_segments": 24, "rings": 12}, _xf(Vector3.ZERO, Vector3.ONE, Vector3(0.5, 0.6, 0.5)), 1],
				["Pillar", "prim", "CylinderMesh", {"top_radius": 0.3, "bottom_radius": 0.4, "height": 2.0, "radial_segments": 16}, _xf(Vector3.ZERO, Vector3.ONE, Vector3(2.2, 1.0, -2.0)), 1],
				["Pill", "prim", "CapsuleMesh", {"radius": 0.3, "height": 1.4, "radial_segments": 16, "rings": 4}, _xf(Vector3(0, 0, 90), Vector3.ONE, Vector3(-1.8, 0.3, 1.5)), 1],
				["Ring", "prim", "TorusMesh", {"inner_radius": 0.3, "outer_radius": 0.6, "rings": 24, "ring_segments": 12}, _xf(Vector3(20, 0, 0), Vector3.ONE, Vector3(-0.2, 0.3, 2.0)), 1],
			],
		},
		{
			"name": "gltf", "size": 128, "pages": 1,
			"scene": "res://world.tscn", "lightmap": "res://world",
			"nodes": [
				["Yard", "prim", "PlaneMesh", {"size": Vector2(5.0, 5.0)}, _xf(Vector3.ZERO, Vector3.ONE, Vector3.ZERO), 0],
				["Rock", "glb", "PrismMesh", {"left_to_right": 0.7, "size": Vector3(1.5, 1.0, 1.2)}, _xf(Vector3(0, 25, 0), Vector3(1.2, 1.0, 1.2), Vector3(-1.0, 0.5, 0.5)), 0],
				["Post", "glb", "CylinderMesh", {"top_radius": 0.2, "bottom_radius": 0.2, "height": 1.6, "radial_segments": 12}, _xf(Vector3.ZERO, Vector3.ONE, Vector3(1.4, 0.8, -1.2)), 0],
			],
		},
		{
			"name": "arraymeshes", "size": 128, "pages": 4,
			"scene": "res://levels/level.tscn", "lightmap": "res://levels/level",
			"nodes": [
				["Ground", "prim", "PlaneMesh", {"size": Vector2(8.0, 8.0)}, _xf(Vector3.ZERO, Vector3.ONE, Vector3.ZERO), 0],
				["Steps", "inline", "BoxMesh", {"size": Vector3(2.0, 0.5, 1.0), "subdivide_width": 2}, _xf(Vector3(0, 45, 0), Vector3(1.0, 1.0, 1.5), Vector3(-2.0, 0.25, -1.0)), 1],
				["Arch", "inline", "CylinderMesh", {"top_radius": 0.8, "bottom_radius": 0.8, "height": 0.4, "radial_segments": 20, "cap_top": false}, _xf(Vector3(90, 0, 0), Vector3.ONE, Vector3(1.5, 0.8, -2.5)), 1],
				["Crate", "res", "BoxMesh", {"size": Vector3(1.0, 1.0, 1.0), "subdivide_depth": 1}, _xf(Vector3(0, 15, 0), Vector3(1.2, 0.8, 1.2), Vector3(2.0, 0.4, 1.5)), 2],
				["Boulder", "tres", "SphereMesh", {"radius": 0.7, "height": 1.2, "radial_segments": 20, "rings": 10}, _xf(Vector3(0, 0, 10), Vector3.ONE, Vector3(-1.0, 0.6, 2.0)), 2],
				["Statue", "tres2", "TorusMesh", {"inner_radius": 0.2, "outer_radius": 0.5, "rings": 20, "ring_segments": 10}, _xf(Vector3(0, 60, 0), Vector3.ONE, Vector3(0.5, 0.5, 0.0)), 3],
				["Prop", "prop", "CylinderMesh", {"top_radius": 0.15, "bottom_radius": 0.25, "height": 1.5, "radial_segments": 12}, _xf(Vector3.ZERO, Vector3.ONE, Vector3(3.0, 0.75, -3.0)), 3],
			],
		},
	]


func _ready() -> void:
	var manifest := []
	for p in _projects():
		var entry = _make_project(p)
		if entry == null:
			return
		manifest.append(entry)
	H.emit_json("corpus.json", manifest)
	H.done(0)


func _emit(project: String, res_path: String, user_path: String) -> void:
	H.emit_path(user_path, project + "__" + res_path.trim_prefix("res://").replace("/", "__"))


func _primitive(type: String, props: Dictionary) -> PrimitiveMesh:
	var mesh: PrimitiveMesh = ClassDB.instantiate(type)
	mesh.add_uv2 = true
	for k in props:
		mesh.set(k, props[k])
	return mesh


# An ArrayMesh holding the primitive's surface as Godot stores it (add_surface_from_arrays of
# surface_get_arrays) and its lightmap size hint. two_surfaces: the surface twice, the second moved
# up, each surface's UV2 squeezed into one half of the unit square.
func _array_mesh(prim: PrimitiveMesh, two_surfaces: bool) -> ArrayMesh:
	var am := ArrayMesh.new()
	var arrays := prim.surface_get_arrays(0)
	if not two_surfaces:
		am.add_surface_from_arrays(Mesh.PRIMITIVE_TRIANGLES, arrays)
		am.lightmap_size_hint = prim.get_lightmap_size_hint()
		return am
	for s in 2:
		var a := arrays.duplicate(true)
		var uv2: PackedVector2Array = a[Mesh.ARRAY_TEX_UV2]
		for i in uv2.size():
			uv2[i] = Vector2(0.5 * uv2[i].x + 0.5 * s, uv2[i].y)
		a[Mesh.ARRAY_TEX_UV2] = uv2
		var v: PackedVector3Array = a[Mesh.ARRAY_VERTEX]
		for i in v.size():
			v[i] = v[i] + Vector3(0.0, 0.9 * s, 0.0)
		a[Mesh.ARRAY_VERTEX] = v
		am.add_surface_from_arrays(Mesh.PRIMITIVE_TRIANGLES, a)
	var hint := prim.get_lightmap_size_hint()
	am.lightmap_size_hint = Vector2i(hint.x * 2, hint.y)
	return am


# Shelf packing of the page's nodes, largest scale first: texel sizes = lightmap size hint × scale.
func _pack(sizes: Array, page_size: int) -> Array:
	var scale := 8.0
	while scale > 0.05:
		var order := range(sizes.size())
		order.sort_custom(func(a, b): return sizes[a].y > sizes[b].y or (sizes[a].y == sizes[b].y and a < b))
		var rects := []
		rects.resize(sizes.size())
		var x := BORDER
		var y := BORDER
		var shelf := 0
		var ok := true
		for i in order:
			var w := maxi(4, int(ceil(sizes[i].x * scale)))
			var h := maxi(4, int(ceil(sizes[i].y * scale)))
			if x + w > page_size - BORDER:
				x = BORDER
				y += shelf + GAP
				shelf = 0
			if x + w > page_size - BORDER or y + h > page_size - BORDER:
				ok = false
				break
			rects[i] = Rect2i(x, y, w, h)
			x += w + GAP
			shelf = maxi(shelf, h)
		if ok:
			return rects
		scale *= 0.9
	return []


func _make_project(p: Dictionary) -> Variant:
	var name: String = p["name"]
	var size: int = p["size"]
	var root := Node3D.new()
	root.name = "World"
	add_child(root)
	var lgi := LightmapGI.new()
	lgi.name = "LightmapGI"
	lgi.directional = true
	var users := []  # [node, path, page, mesh]
	var keep := []   # instanced PackedScenes: alive (in the resource cache) until the scene is packed
	for n in p["nodes"]:
		var node_name: String = n[0]
		var kind: String = n[1]
		var prim := _primitive(n[2], n[3])
		var mesh: Mesh = prim
		if kind == "prim":
			prim.resource_scene_unique_id = node_name
		elif kind == "inline":
			mesh = _array_mesh(prim, false)
			mesh.resource_scene_unique_id = node_name
		elif kind in ["res", "tres", "tres2"]:
			mesh = _array_mesh(prim, kind == "tres2")
			var file := "res://meshes/%s.%s" % [node_name.to_lower(), "res" if kind == "res" else "tres"]
			var tmp := "user://" + file.get_file()
			if ResourceSaver.save(mesh, tmp) != OK:
				H.fail("%s: save %s" % [name, file])
				return null
			_emit(name, file, tmp)
			mesh.take_over_path(file)
		var mi := MeshInstance3D.new()
		mi.mesh = mesh
		if kind == "glb":
			# A glTF file written by Godot's own exporter (UV2 as TEXCOORD_1), read back by
			# GLTFDocument as an import would, and instanced from its res:// path.
			var file := "res://models/%s.glb" % node_name.to_lower()
			var src := Node3D.new()
			src.name = node_name.to_lower()
			mi.mesh = _array_mesh(prim, false)
			mi.name = node_name + "Mesh"
			src.add_child(mi)
			mi.owner = src
			var doc := GLTFDocument.new()
			var st := GLTFState.new()
			if doc.append_from_scene(src, st) != OK or doc.write_to_filesystem(st, "user://model.glb") != OK:
				H.fail("%s: glTF export of %s" % [name, file])
				return null
			src.free()
			_emit(name, file, "user://model.glb")
			var doc2 := GLTFDocument.new()
			var st2 := GLTFState.new()
			if doc2.append_from_file("user://model.glb", st2) != OK:
				H.fail("%s: glTF read back of %s" % [name, file])
				return null
			var imported: Node = doc2.generate_scene(st2)
			for c in imported.find_children("*", "", true, false):
				c.owner = imported
			var packed_glb := H.pack_scene(imported)
			if packed_glb == null:
				return null
			imported.free()
			# Packing a node instanced from a .glb path fails here (no loader for .glb at run time):
			# the instance is packed from a .tscn path, renamed in the saved text below.
			packed_glb.take_over_path(file.get_basename() + "_glb.tscn")
			keep.append(packed_glb)
			p["renames"] = p.get("renames", []) + [[file.get_basename() + "_glb.tscn", file]]
			var g_inst: Node3D = packed_glb.instantiate()
			g_inst.name = node_name
			g_inst.transform = n[4]
			root.add_child(g_inst)
			g_inst.owner = root
			var found := g_inst.find_children("*", "MeshInstance3D", true, false)
			if found.size() != 1:
				H.fail("%s: %s: %d meshes after import" % [name, file, found.size()])
				return null
			# The imported mesh has no size hint (the editor's importer would set one): the source's.
			users.append([found[0], String(root.get_path_to(found[0])), n[5], prim])
			continue
		if kind == "prop":
			# A scene of its own, instanced: its node "Lamp" is the lightmap user.
			prim.resource_scene_unique_id = "Lamp"
			var prop := Node3D.new()
			prop.name = "Prop"
			mi.name = "Lamp"
			prop.add_child(mi)
			mi.owner = prop
			var packed := H.pack_scene(prop)
			if packed == null:
				return null
			var file := "res://props/prop.tscn"
			if ResourceSaver.save(packed, "user://prop.tscn") != OK:
				H.fail("%s: save %s" % [name, file])
				return null
			_emit(name, file, "user://prop.tscn")
			prop.free()
			packed.take_over_path(file)
			keep.append(packed)
			var inst: Node3D = packed.instantiate()
			inst.name = node_name
			inst.transform = n[4]
			root.add_child(inst)
			inst.owner = root
			users.append([inst.get_node("Lamp"), node_name + "/Lamp", n[5], mesh])
			continue
		mi.name = node_name
		mi.transform = n[4]
		root.add_child(mi)
		mi.owner = root
		users.append([mi, node_name, n[5], mesh])
	root.add_child(lgi)
	lgi.owner = root

	# The atlas: each page's users packed by their lightmap size hints.
	var rects := []
	rects.resize(users.size())
	for page in p["pages"]:
		var idx := []
		var sizes := []
		for i in users.size():
			if users[i][2] == page:
				idx.append(i)
				sizes.append(Vector2(users[i][3].get_lightmap_size_hint()))
		var packed := _pack(sizes, size)
		if idx.is_empty() or packed.is_empty():
			H.fail("%s: page %d: nothing to place or no packing" % [name, page])
			return null
		for k in idx.size():
			rects[idx[k]] = packed[k]

	var data := LightmapGIData.new()
	var tex := CompressedTexture2DArray.new()
	tex.take_over_path(p["lightmap"] + ".exr")
	data.lightmap_textures = [tex]
	data.uses_spherical_harmonics = true
	data._set_uses_packed_directional(true)
	var out_users := []
	for i in users.size():
		var r: Rect2i = rects[i]
		var uv_scale := Rect2(Vector2(r.position) / size, Vector2(r.size) / size)
		var path := NodePath("../" + users[i][1])
		data.add_user(path, uv_scale, users[i][2], -1)
		var mi: MeshInstance3D = users[i][0]
		if lgi.get_node_or_null(path) != mi:
			H.fail("%s: %s does not name the node from the LightmapGI" % [name, path])
			return null
		out_users.append(_describe_user(mi, String(path), users[i][2], r, uv_scale))
	var lmbake: String = p["lightmap"] + ".lmbake"
	if ResourceSaver.save(data, "user://bake.lmbake") != OK:
		H.fail("%s: save %s" % [name, lmbake])
		return null
	_emit(name, lmbake, "user://bake.lmbake")
	var back = ResourceLoader.load("user://bake.lmbake", "", ResourceLoader.CACHE_MODE_IGNORE)
	if back == null or back.get_user_count() != users.size():
		H.fail("%s: %s read back wrong" % [name, lmbake])
		return null
	data.take_over_path(lmbake)
	lgi.light_data = data
	if p.has("swapped"):
		# A wrong bake for the tests: the same users with two of their rectangles swapped.
		var wrong := LightmapGIData.new()
		wrong.lightmap_textures = [tex]
		wrong.uses_spherical_harmonics = true
		wrong._set_uses_packed_directional(true)
		var a: int = p["swapped"][0]
		var b: int = p["swapped"][1]
		for i in users.size():
			var j := b if i == a else (a if i == b else i)
			var r: Rect2i = rects[j]
			wrong.add_user(NodePath("../" + users[i][1]), Rect2(Vector2(r.position) / size, Vector2(r.size) / size), users[j][2], -1)
		if ResourceSaver.save(wrong, "user://wrong.lmbake") != OK:
			H.fail("%s: save the swapped .lmbake" % name)
			return null
		H.emit_path("user://wrong.lmbake", "negative__%s_swapped.lmbake" % name)

	var scene := H.pack_scene(root)
	if scene == null:
		return null
	if ResourceSaver.save(scene, "user://scene.tscn") != OK:
		H.fail("%s: save %s" % [name, p["scene"]])
		return null
	if p.has("renames"):
		var text := FileAccess.get_file_as_string("user://scene.tscn")
		for r in p["renames"]:
			text = text.replace('path="%s"' % r[0], 'path="%s"' % r[1])
		var fw := FileAccess.open("user://scene.tscn", FileAccess.WRITE)
		fw.store_string(text)
		fw.close()
	_emit(name, p["scene"], "user://scene.tscn")
	root.free()
	return {
		"name": name, "size": size, "pages": p["pages"], "scene": p["scene"],
		"lightmap": p["lightmap"], "users": out_users,
		"godot": Engine.get_version_info()["string"],
	}


# The user's mesh in world space (the LightmapGI and its parents sit at the origin): positions by
# the global transform, normals by its inverse transpose (normalised), UV2 and indices as stored.
func _describe_user(mi: MeshInstance3D, path: String, page: int, r: Rect2i, uv_scale: Rect2) -> Dictionary:
	var xf := mi.global_transform
	var nb := xf.basis.inverse().transposed()
	var surfaces := []
	for s in mi.mesh.get_surface_count():
		var a := mi.mesh.surface_get_arrays(s)
		var v := PackedVector3Array()
		for p in a[Mesh.ARRAY_VERTEX]:
			v.append(xf * p)
		var nn := PackedVector3Array()
		for n in a[Mesh.ARRAY_NORMAL]:
			nn.append((nb * n).normalized())
		surfaces.append({"vertex": J.to_json(v), "normal": J.to_json(nn), "uv2": J.to_json(a[Mesh.ARRAY_TEX_UV2]),
			"index": J.to_json(a[Mesh.ARRAY_INDEX])})
	return {
		"path": path, "mesh": mi.mesh.get_class(), "page": page,
		"rect_texels": [r.position.x, r.position.y, r.size.x, r.size.y],
		"uv_scale": J.to_json(uv_scale), "surfaces": surfaces,
	}
