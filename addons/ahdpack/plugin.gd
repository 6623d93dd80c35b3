# The editor side of the add-on (Project Settings > Plugins > ahdpack). The runtime needs no plugin:
# AhdLightmap (ahd_lightmap.gd) and ahd_lightmap.gdshader work without it.
@tool
extends EditorPlugin
