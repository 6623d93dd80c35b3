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
		# Issue 40's FBX rows (emitted to wild.json): .fbx instances imported with Static Lightmaps,
		# their NAME.fbx.unwrap_cache written as Godot's importer writes it (_fbx_unwrap below).
		{
			"name": "fbx", "size": 128, "pages": 1, "json": "wild",
			"scene": "res://scenes/room.tscn", "lightmap": "res://scenes/room",
			"nodes": [
				["Room", "fbx", "room.fbx", {}, _xf(Vector3(0, 20, 0), Vector3.ONE, Vector3(-1.0, 0.0, -1.0)), 0],
				["Corner", "fbx", "room_zup.fbx", {}, _xf(Vector3.ZERO, Vector3(1.0, 1.0, 1.5), Vector3(2.0, 0.0, 1.0)), 0],
			],
		},
		{
			"name": "fbx_dropped", "size": 128, "pages": 1, "json": "wild",
			"scene": "res://level.tscn", "lightmap": "res://level",
			"nodes": [
				["Tiles", "fbx", "tiles.fbx", {}, _xf(Vector3(0, -30, 0), Vector3.ONE, Vector3(0.0, 0.0, 0.5)), 0],
			],
		},
	]


func _ready() -> void:
	var manifest := []
	var wild := []
	for p in _projects():
		var entry = _make_project(p)
		if entry == null:
			return
		if p.get("json", "") == "wild":
			wild.append(entry)
		else:
			manifest.append(entry)
	H.emit_json("corpus.json", manifest)
	H.emit_json("wild.json", wild)
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
		var prim: PrimitiveMesh = null if kind == "fbx" else _primitive(n[2], n[3])
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
		if kind == "fbx":
			if not _add_fbx(name, n, root, users, keep, p):
				return null
			continue
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


# An FBX file (tests/data/godot/handmade, packed as res://fbx/NAME.fbx) imported by Godot's own FBX
# importer (FBXDocument, ufbx) and given lightmap UV2 as the editor's scene importer does with
# meshes/light_baking = Static Lightmaps: each mesh node in tree order is unwrapped with the key of
# ImporterMesh::lightmap_unwrap_cached and its entry goes into NAME.fbx.unwrap_cache the way
# ResourceImporterScene::_generate_meshes collects them (_fbx_unwrap). The nodes of the file, with
# their meshes now carrying UV2, are instanced under `n[0]`; each mesh node is a lightmap user.
func _add_fbx(name: String, n: Array, root: Node3D, users: Array, keep: Array, p: Dictionary) -> bool:
	var file := "res://models/" + String(n[2])
	var doc = ClassDB.instantiate("FBXDocument")
	var st = ClassDB.instantiate("FBXState")
	if doc == null or doc.append_from_file("res://fbx/" + String(n[2]), st) != OK:
		H.fail("%s: FBX import of %s" % [name, n[2]])
		return false
	var imported: Node = doc.generate_scene(st)
	# The importer's meshes (ImporterMesh: uncompressed normals, as the unwrap gets them), by node name.
	var importer_meshes := {}
	for gn in st.get_nodes():
		if gn.mesh >= 0:
			importer_meshes[String(gn.resource_name)] = st.get_meshes()[gn.mesh].mesh
	var found := imported.find_children("*", "MeshInstance3D", true, false)
	if found.is_empty():
		H.fail("%s: %s: no mesh node" % [name, file])
		return false
	var texel := 0.2  # meshes/lightmap_texel_size, the import default
	var cache := []  # entries' bytes, as _generate_meshes keeps them
	for mi in found:
		var im = importer_meshes.get(String(mi.name))
		if im == null:
			H.fail("%s: %s: no importer mesh for node %s" % [name, file, mi.name])
			return false
		# The node's transform in the imported scene, as _generate_meshes accumulates it.
		var xf := Transform3D()
		var walk: Node = mi
		while walk != null and walk is Node3D:
			xf = walk.transform * xf
			walk = walk.get_parent()
		var u = _fbx_unwrap(im, xf, texel)
		if u == null:
			H.fail("%s: %s: unwrap of %s" % [name, file, mi.name])
			return false
		_cache_insert(cache, u["entry"])
		mi.mesh = u["mesh"]
	var bytes := PackedByteArray()
	bytes.resize(4)
	bytes.encode_u32(0, cache.size())
	for e in cache:
		bytes.append_array(e)
	H.emit_file(name + "__" + file.trim_prefix("res://").replace("/", "__") + ".unwrap_cache", bytes)
	H.emit_file(name + "__" + file.trim_prefix("res://").replace("/", "__"), FileAccess.get_file_as_bytes("res://fbx/" + String(n[2])))
	for c in imported.find_children("*", "", true, false):
		c.owner = imported
	var packed := H.pack_scene(imported)
	if packed == null:
		return false
	imported.free()
	# As for .glb: packed from a stand-in .tscn path, renamed to the .fbx in the saved text.
	packed.take_over_path(file.get_basename() + "_fbx.tscn")
	keep.append(packed)
	p["renames"] = p.get("renames", []) + [[file.get_basename() + "_fbx.tscn", file]]
	var inst: Node3D = packed.instantiate()
	inst.name = n[0]
	inst.transform = n[4]
	root.add_child(inst)
	inst.owner = root
	for m in inst.find_children("*", "MeshInstance3D", true, false):
		users.append([m, String(root.get_path_to(m)), n[5], m.mesh])
	return true


# Godot's collection of cache entries (editor/import/3d/resource_importer_scene.cpp,
# _generate_meshes): the first entry is kept; a later one is inserted before the first entry whose
# key (as a hex string) is greater, and dropped when none is (godotengine/godot#122494).
static func _cache_insert(cache: Array, entry: PackedByteArray) -> void:
	if cache.is_empty():
		cache.append(entry)
		return
	var k := entry.slice(0, 16).hex_encode()
	for i in cache.size():
		var ki: String = cache[i].slice(0, 16).hex_encode()
		if k < ki:
			cache.insert(i, entry)
			return
		if k == ki:
			return


# One mesh's unwrap as ImporterMesh::lightmap_unwrap_cached hands it to the unwrapper
# (scene/resources/importer_mesh.cpp): surfaces concatenated, positions by the scale of `xf` only,
# normals by that scale's inverse transpose and normalised, triangles with an edge shorter than
# sqrt(1.19209290e-7) dropped; its key is the MD5 of the texel size (float), the indices (int32),
# the positions and the normals (float triples) — modules/xatlas_unwrap/register_types.cpp, which
# also gives the entry's layout: key, size hint (x, y), vertex count, source vertex per vertex,
# UV2 pairs, index count, indices. The UV2 itself is a stand-in for xatlas, which the web build
# lacks (an editor-only module): one planar chart per mesh (projected along its mean normal's
# largest axis), one texel of margin, the size hint its extent over the texel size. Returns
# {"entry": bytes, "mesh": the ArrayMesh the import ends with (UV2 added, size hint set)}.
static func _fbx_unwrap(im, xf: Transform3D, texel: float) -> Variant:
	var b := xf.basis
	var t := Transform3D().scaled(Vector3(b.x.length(), b.y.length(), b.z.length()))
	var nb := t.basis.inverse().transposed()
	var pos := PackedFloat32Array()
	var nrm := PackedFloat32Array()
	var idx := PackedInt32Array()
	var src_v := PackedVector3Array()
	var src_n := PackedVector3Array()
	var scaled := PackedVector3Array()
	var mean := Vector3.ZERO
	var eps := 1.19209290e-7
	for s in im.get_surface_count():
		var a: Array = im.get_surface_arrays(s)
		var V: PackedVector3Array = a[Mesh.ARRAY_VERTEX]
		var N: PackedVector3Array = a[Mesh.ARRAY_NORMAL]
		var I: PackedInt32Array = a[Mesh.ARRAY_INDEX]
		if N.size() != V.size() or I.is_empty():
			return null
		var ofs := src_v.size()
		for j in V.size():
			var v := t * V[j]
			var nn := (nb * N[j]).normalized()
			for c in 3:
				pos.append(v[c])
				nrm.append(nn[c])
			src_v.append(V[j])
			src_n.append(N[j])
			scaled.append(v)
			mean += nn
		for j in I.size() / 3:
			var p0 := t * V[I[j * 3]]
			var p1 := t * V[I[j * 3 + 1]]
			var p2 := t * V[I[j * 3 + 2]]
			if (p0 - p1).length_squared() < eps or (p1 - p2).length_squared() < eps or (p2 - p0).length_squared() < eps:
				continue
			for c in 3:
				idx.append(ofs + I[j * 3 + c])
	var hc := HashingContext.new()
	hc.start(HashingContext.HASH_MD5)
	var ts := PackedFloat32Array()
	ts.append(texel)
	hc.update(ts.to_byte_array())
	hc.update(idx.to_byte_array())
	hc.update(pos.to_byte_array())
	hc.update(nrm.to_byte_array())
	var key := hc.finish()
	# The stand-in chart: project on the two axes other than the mean normal's largest.
	var ax := 0 if absf(mean.x) >= maxf(absf(mean.y), absf(mean.z)) else (1 if absf(mean.y) >= absf(mean.z) else 2)
	var ua := (ax + 1) % 3
	var va := (ax + 2) % 3
	var lo := Vector2(INF, INF)
	var hi := Vector2(-INF, -INF)
	for v in scaled:
		lo = Vector2(minf(lo.x, v[ua]), minf(lo.y, v[va]))
		hi = Vector2(maxf(hi.x, v[ua]), maxf(hi.y, v[va]))
	var w := int(ceil((hi.x - lo.x) / texel)) + 2
	var h := int(ceil((hi.y - lo.y) / texel)) + 2
	var uv2 := PackedVector2Array()
	var uvf := PackedFloat32Array()
	for v in scaled:
		var q := Vector2(((v[ua] - lo.x) / texel + 1.0) / w, ((v[va] - lo.y) / texel + 1.0) / h)
		uv2.append(q)
		uvf.append(q.x)
		uvf.append(q.y)
	var e := PackedByteArray()
	e.append_array(key)
	var head := PackedInt32Array()
	head.append(w)
	head.append(h)
	head.append(scaled.size())
	for i in scaled.size():
		head.append(i)  # source vertex: one chart, no vertex split
	e.append_array(head.to_byte_array())
	e.append_array(uvf.to_byte_array())
	var count := PackedInt32Array()
	count.append(idx.size())
	e.append_array(count.to_byte_array())
	e.append_array(idx.to_byte_array())
	# The mesh the import ends with: the unwrapped vertices (source vertex, UV2) and triangles.
	var arrays := []
	arrays.resize(Mesh.ARRAY_MAX)
	arrays[Mesh.ARRAY_VERTEX] = src_v
	arrays[Mesh.ARRAY_NORMAL] = src_n
	arrays[Mesh.ARRAY_TEX_UV2] = uv2
	arrays[Mesh.ARRAY_INDEX] = idx
	var am := ArrayMesh.new()
	am.add_surface_from_arrays(Mesh.PRIMITIVE_TRIANGLES, arrays)
	am.lightmap_size_hint = Vector2i(w, h)
	return {"entry": e, "mesh": am}
