# An ahdpack conversion in Godot 4: reads the manifest NAME.json that `ahdpack convert` writes,
# loads its planes (KTX2 or DDS) as Texture2DArray (one layer per atlas page) and makes the
# ShaderMaterial (ahd_lightmap.gdshader) that lights a mesh instance with the AHD decode at its
# atlas rectangle and page. docs/engine-integration.md "Godot 4 (tested)".
#
#   const AhdLightmap = preload("res://addons/ahdpack/ahd_lightmap.gd")   # or the class name
#   var lm := AhdLightmap.new()
#   if lm.open("res://lightmaps/scene.json") != OK: push_error(lm.error)
#   lm.apply($Floor, Rect2(0, 0, 0.5, 1), 0)   # material_override + LightmapGI off for $Floor
#
# Planes load with Godot's own loaders (Image.load_ktx_from_buffer / load_dds_from_buffer) with the
# files' mips. Godot's KTX loader refuses array files and does not map VK_FORMAT_R8G8B8A8_UNORM
# (modules/ktx/texture_loader_ktx.cpp: "Unsupported array KTX texture file"): those, and
# zstd-supercompressed files (--zstd), are read here from the KTX2 level index
# (read_ktx2_layers). B10G11R11 (profile packed-float) has no Godot Image format: refused.
@tool
class_name AhdLightmap
extends RefCounted

const SHADER_PATH := "res://addons/ahdpack/ahd_lightmap.gdshader"

var manifest: Dictionary = {}
var error: String = ""
var layers: int = 1
var iz: Texture2DArray
var dir: Texture2DArray  # dir, or dirratio for the packed profiles; null when not directional
var ratio: Texture2DArray  # null for the packed profiles and when not directional
# How the channels landed (see the shader's ahd_dir_in_ra / ahd_ratio_source).
var dir_in_ra := false
var ratio_source := 0
# The format Godot gave each plane (Image.Format), by plane name.
var image_formats: Dictionary = {}


# Reads the manifest at `path` and loads its planes. OK, or an error code with `error` set to
# "<file>: <cause>".
func open(path: String) -> Error:
	var text := FileAccess.get_file_as_string(path)
	if text == "":
		return _fail(path + ": cannot read (" + error_string(FileAccess.get_open_error()) + ")")
	var m = JSON.parse_string(text)
	if typeof(m) != TYPE_DICTIONARY or m.get("format", "") != "ahdpack-manifest":
		return _fail(path + ": not an ahdpack manifest")
	if int(m.get("version", 0)) != 1:
		return _fail(path + ": manifest version %s (this add-on reads version 1)" % str(m.get("version")))
	manifest = m
	layers = int(m.get("layers", 1))
	var base := path.get_base_dir()
	for p in m["planes"]:
		if not (str(p["name"]) in ["iz", "dir", "ratio", "dirratio"]):
			continue  # e.g. "coverage": not used for lighting
		var file := base.path_join(str(p["file"]))
		var images := _load_plane(file, str(p["format"]))
		if images.is_empty():
			return ERR_FILE_CORRUPT
		if images.size() != layers:
			return _fail(file + ": %d layers, the manifest says %d" % [images.size(), layers])
		var tex := Texture2DArray.new()
		if tex.create_from_images(images) != OK:
			return _fail(file + ": Texture2DArray.create_from_images failed (format %d)" % images[0].get_format())
		image_formats[str(p["name"])] = images[0].get_format()
		match str(p["name"]):
			"iz":
				iz = tex
			"dir":
				dir = tex
				dir_in_ra = images[0].get_format() == Image.FORMAT_LA8
			"dirratio":
				dir = tex
				ratio_source = 2
			"ratio":
				ratio = tex
				ratio_source = 1 if m["decode"].get("ratio_form", "luminance") == "rgb" else 0
	if iz == null:
		return _fail(path + ": no iz plane")
	if bool(m.get("directional", true)) and dir == null:
		return _fail(path + ": directional but no dir plane")
	return OK


# A ShaderMaterial for one instance: the instance's atlas rectangle (Godot's LightmapGI user
# rect: position and size in [0,1]) and page (array layer).
func make_material(rect := Rect2(0, 0, 1, 1), page := 0, shader: Shader = null) -> ShaderMaterial:
	var mat := ShaderMaterial.new()
	mat.shader = shader if shader != null else load(SHADER_PATH)
	var d: Dictionary = manifest["decode"]
	mat.set_shader_parameter("ahd_iz", iz)
	mat.set_shader_parameter("ahd_directional", dir != null and bool(manifest.get("directional", true)))
	if dir != null:
		mat.set_shader_parameter("ahd_dir", dir)
	if ratio != null:
		mat.set_shader_parameter("ahd_ratio", ratio)
	mat.set_shader_parameter("ahd_dir_in_ra", dir_in_ra)
	mat.set_shader_parameter("ahd_ratio_source", ratio_source)
	mat.set_shader_parameter("ahd_dz_min", float(d.get("dz_min", 0.05)))
	mat.set_shader_parameter("ahd_iz_scale", float(d.get("iz_scale", 1.0)))
	mat.set_shader_parameter("ahd_world_frame", str(d.get("direction_frame", "tangent")) == "normal-frame")
	mat.set_shader_parameter("ahd_uv_rect", Vector4(rect.position.x, rect.position.y, rect.size.x, rect.size.y))
	mat.set_shader_parameter("ahd_page", float(page))
	return mat


# Lights `node` with this lightmap at `rect` and `page`: sets its material_override and turns
# Godot's own lightmap (LightmapGI) and GI probes off for it (gi_mode = GI_MODE_DISABLED), so it is
# not lit twice. Returns the material (set albedo, albedo_texture, normal_texture on it).
func apply(node: GeometryInstance3D, rect := Rect2(0, 0, 1, 1), page := 0) -> ShaderMaterial:
	var mat := make_material(rect, page)
	node.material_override = mat
	node.gi_mode = GeometryInstance3D.GI_MODE_DISABLED
	return mat


func _fail(message: String) -> Error:
	error = message
	return ERR_INVALID_DATA


# One Image per layer, with every mip level of the file.
func _load_plane(file: String, format: String) -> Array[Image]:
	var bytes := FileAccess.get_file_as_bytes(file)
	if bytes.is_empty():
		_fail(file + ": cannot read (" + error_string(FileAccess.get_open_error()) + ")")
		return []
	var out: Array[Image] = []
	if file.get_extension().to_lower() == "dds":
		if layers > 1:
			_fail(file + ": DDS arrays are not read by this add-on (convert with -o NAME.ktx2)")
			return []
		var img := Image.new()
		if img.load_dds_from_buffer(bytes) != OK:
			_fail(file + ": Godot's DDS loader refused it (format " + format + ")")
			return []
		out.append(img)
		return out
	var h := ktx2_header(bytes)
	if h.is_empty():
		_fail(file + ": not a KTX2 file")
		return []
	if h["vk_format"] == 122:
		_fail(file + ": B10G11R11 has no Godot Image format (convert with --profile uncompressed or pc-bc)")
		return []
	if h["layers"] <= 1 and h["supercompression"] == 0 and h["vk_format"] in GODOT_KTX_FORMATS:
		var img := Image.new()
		if img.load_ktx_from_buffer(bytes) != OK:
			_fail(file + ": Godot's KTX loader refused it (format " + format + ")")
			return []
		out.append(img)
		return out
	out = read_ktx2_layers(bytes, h)
	if out.is_empty():
		_fail(file + ": " + _ktx_error)
	return out


# vkFormat -> Image.Format for the formats ahdpack writes. Godot's own KTX loader maps all but
# R8G8B8A8_UNORM (37), and loads R8 as FORMAT_L8 and R8G8 as FORMAT_LA8
# (modules/ktx/texture_loader_ktx.cpp); read_ktx2_layers keeps R8 and RG8.
const VK_TO_IMAGE := {
	9: Image.FORMAT_R8, 16: Image.FORMAT_RG8, 37: Image.FORMAT_RGBA8, 97: Image.FORMAT_RGBAH,
	123: Image.FORMAT_RGBE9995, 139: Image.FORMAT_RGTC_R, 141: Image.FORMAT_RGTC_RG,
	143: Image.FORMAT_BPTC_RGBFU,
}
const GODOT_KTX_FORMATS := [9, 16, 97, 123, 139, 141, 143]

var _ktx_error := ""


# The KTX2 header fields used here (KTX 2.0 specification, section 3), or {} if not KTX2.
static func ktx2_header(b: PackedByteArray) -> Dictionary:
	const ID := [0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A]
	if b.size() < 80:
		return {}
	for i in 12:
		if b[i] != ID[i]:
			return {}
	return {
		"vk_format": b.decode_u32(12), "width": b.decode_u32(20), "height": b.decode_u32(24),
		"layers": b.decode_u32(32), "faces": b.decode_u32(36), "levels": maxi(1, b.decode_u32(40)),
		"supercompression": b.decode_u32(44),
	}


# Every layer of a KTX2 file as an Image with all its mips: the level index gives each level's
# bytes, which hold the layers one after the other (KTX 2.0, section 3.9); zstd levels
# (supercompression 2) are inflated with Godot's own zstd.
func read_ktx2_layers(b: PackedByteArray, h: Dictionary) -> Array[Image]:
	var out: Array[Image] = []
	if not VK_TO_IMAGE.has(h["vk_format"]):
		_ktx_error = "vkFormat %d is not read by this add-on" % h["vk_format"]
		return out
	if h["faces"] != 1 or not (h["supercompression"] in [0, 2]):
		_ktx_error = "cube maps and supercompression %d are not read by this add-on" % h["supercompression"]
		return out
	var n_layers: int = maxi(1, h["layers"])
	var levels: int = h["levels"]
	var per_layer: Array[PackedByteArray] = []
	per_layer.resize(n_layers)
	for level in levels:
		var at := 80 + level * 24
		if at + 24 > b.size():
			_ktx_error = "truncated level index"
			return out
		var off := b.decode_u64(at)
		var size := b.decode_u64(at + 8)
		var full := b.decode_u64(at + 16)
		if off + size > b.size():
			_ktx_error = "level %d runs past the end of the file" % level
			return out
		var data := b.slice(off, off + size)
		if h["supercompression"] == 2:
			data = data.decompress(full, FileAccess.COMPRESSION_ZSTD)
			if data.size() != full:
				_ktx_error = "level %d: zstd data does not inflate to %d bytes" % [level, full]
				return out
		if data.size() % n_layers != 0:
			_ktx_error = "level %d: %d bytes do not split into %d layers" % [level, data.size(), n_layers]
			return out
		var step := data.size() / n_layers
		for layer in n_layers:
			var chain := per_layer[layer]  # a packed array is a value: append, then store back
			chain.append_array(data.slice(layer * step, (layer + 1) * step))
			per_layer[layer] = chain
	for layer in n_layers:
		var img := Image.create_from_data(h["width"], h["height"], levels > 1, VK_TO_IMAGE[h["vk_format"]], per_layer[layer])
		if img == null or img.get_mipmap_count() != levels - 1:
			_ktx_error = "layer %d: Godot does not take %d mip levels of %dx%d" % [layer, levels, h["width"], h["height"]]
			return []
		out.append(img)
	return out
