# Attach to a MeshInstance3D (any GeometryInstance3D) to light it from an ahdpack conversion at its
# atlas rectangle and page. The scene stores only the manifest's path: `ahdpack convert` names the
# plane files by their content (NAME.iz.<hash>.ktx2), so they change at every re-cook, but NAME.json
# keeps its name and names the current planes; nothing in the scene points at a plane file.
# Runs in the game only (not a tool script: the material with its textures is never saved into the
# scene). docs/engine-integration.md "Godot 4 (tested)".
extends GeometryInstance3D

const AhdLightmapScript = preload("res://addons/ahdpack/ahd_lightmap.gd")

@export_file("*.json") var manifest := ""
## The instance's rectangle in the atlas, position and size in [0, 1] (Godot's LightmapGI user rect).
@export var atlas_rect := Rect2(0, 0, 1, 1)
## The atlas page: the planes' array layer.
@export var page := 0
@export var albedo := Color(1, 1, 1)
@export var albedo_texture: Texture2D
@export var normal_texture: Texture2D
@export var energy := 1.0

# One loaded conversion per manifest path, shared by every instance of the scene.
static var _loaded := {}


func _ready() -> void:
	if manifest == "":
		return
	var lm = _loaded.get(manifest)
	if lm == null:
		lm = AhdLightmapScript.new()
		if lm.open(manifest) != OK:
			push_error("ahdpack: " + lm.error)
			return
		_loaded[manifest] = lm
	var mat: ShaderMaterial = lm.apply(self, atlas_rect, page)
	mat.set_shader_parameter("albedo", albedo)
	if albedo_texture != null:
		mat.set_shader_parameter("albedo_texture", albedo_texture)
	if normal_texture != null:
		mat.set_shader_parameter("normal_texture", normal_texture)
		mat.set_shader_parameter("use_normal_map", true)
	mat.set_shader_parameter("ahd_energy", energy)
