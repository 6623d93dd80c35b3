# Mesh arrays as JSON for the generators (copied into every packed project as res://mesh_json.gd):
# flat float lists for vectors, ints for indices; an absent array is left out.
extends RefCounted


static func to_json(v: Variant) -> Variant:
	match typeof(v):
		TYPE_VECTOR2, TYPE_VECTOR2I:
			return [v.x, v.y]
		TYPE_VECTOR3, TYPE_VECTOR3I:
			return [v.x, v.y, v.z]
		TYPE_RECT2, TYPE_RECT2I:
			return [v.position.x, v.position.y, v.size.x, v.size.y]
		TYPE_AABB:
			return [v.position.x, v.position.y, v.position.z, v.size.x, v.size.y, v.size.z]
		TYPE_PACKED_VECTOR2_ARRAY:
			var o := []
			for e in v:
				o.append(e.x)
				o.append(e.y)
			return o
		TYPE_PACKED_VECTOR3_ARRAY:
			var o := []
			for e in v:
				o.append(e.x)
				o.append(e.y)
				o.append(e.z)
			return o
		TYPE_PACKED_FLOAT32_ARRAY, TYPE_PACKED_FLOAT64_ARRAY, TYPE_PACKED_INT32_ARRAY, TYPE_PACKED_INT64_ARRAY:
			return Array(v)
	return v


const NAMES := {
	Mesh.ARRAY_VERTEX: "vertex",
	Mesh.ARRAY_NORMAL: "normal",
	Mesh.ARRAY_TANGENT: "tangent",
	Mesh.ARRAY_TEX_UV: "uv",
	Mesh.ARRAY_TEX_UV2: "uv2",
	Mesh.ARRAY_INDEX: "index",
}


# [{"vertex": [...], "normal": [...], ...}] for every surface of `mesh` (surface_get_arrays).
# `which`: the array kinds to keep (Mesh.ARRAY_*).
static func surfaces(mesh: Mesh, which: Array = [Mesh.ARRAY_VERTEX, Mesh.ARRAY_NORMAL, Mesh.ARRAY_TEX_UV2, Mesh.ARRAY_INDEX]) -> Array:
	var out := []
	for s in mesh.get_surface_count():
		var arrays := mesh.surface_get_arrays(s)
		var d := {}
		for k in which:
			var a = arrays[k]
			if a == null or a.size() == 0:
				continue
			d[NAMES[k]] = to_json(a)
		out.append(d)
	return out
