// ahdpack: export what `ahdpack convert` needs from a baked Unity scene (docs/bakers.md "Unity").
//
// Menu Tools > ahdpack > Export Lightmapped Scene writes, beside the scene's lightmaps folder
// (Assets/<Scene>/, where Unity keeps Lightmap-N_comp_light.exr and _comp_dir.png):
//   <Scene>.ahdpack.gltf            every lightmapped renderer's mesh as one glTF node, in world
//                                   space, its lightmap UVs (Mesh.uv2, else Mesh.uv) as TEXCOORD_1
//   <Scene>.ahdpack-placement.json  {"placements": [{"node", "page", "scale", "offset"}]} from
//                                   Renderer.lightmapIndex and Renderer.lightmapScaleOffset
// Built-in meshes (Cube, Plane, …) are exported like any other: the mesh data is read, not a file.
// Then, per lightmap page N:
//   ahdpack convert Assets/<Scene>/Lightmap-N_comp_light.exr --mesh <Scene>.ahdpack.gltf \
//       --placement <Scene>.ahdpack-placement.json -o out/lightmap-N.ktx2 --profile pc-bc
// (the page is read from the file name Lightmap-N; --page N overrides).
//
// Written from Unity's documented API (Renderer.lightmapIndex, Renderer.lightmapScaleOffset,
// Mesh.uv2, Mesh.GetTriangles, LightmapSettings.lightmaps, Transform.localToWorldMatrix). It could
// not be run where ahdpack is developed (no Unity there); the tests feed ahdpack files in exactly
// the form this script writes (tests/unit/baker_unity_bevy_test.cpp).
//
// Axes: Unity is left-handed (+x right, +y up, +z forward), glTF right-handed; as Unity's glTF
// exporters do, x is negated (positions and normals) and the winding reversed. The ahdpack presets
// of Unity's bakes take the mesh back into Unity's world ("mesh_axes": ["-x", "y", "z"]).
// UVs: glTF's v runs down, Unity's up: v is stored as 1 − v.
#if UNITY_EDITOR
using System.Collections.Generic;
using System.Globalization;
using System.IO;
using System.Text;
using UnityEditor;
using UnityEditor.SceneManagement;
using UnityEngine;

public static class AhdpackLightmapExport
{
    [MenuItem("Tools/ahdpack/Export Lightmapped Scene")]
    public static void Export()
    {
        var scene = EditorSceneManager.GetActiveScene();
        if (string.IsNullOrEmpty(scene.path)) { Debug.LogError("ahdpack: save the scene first"); return; }
        string dir = Path.Combine(Path.GetDirectoryName(scene.path), scene.name);
        Directory.CreateDirectory(dir);
        string gltfPath = Path.Combine(dir, scene.name + ".ahdpack.gltf");
        string placementPath = Path.Combine(dir, scene.name + ".ahdpack-placement.json");
        int n = Write(gltfPath, placementPath);
        Debug.Log($"ahdpack: {n} lightmapped renderer(s) -> {gltfPath}, {placementPath}");
    }

    static string F(float v) { return v.ToString("R", CultureInfo.InvariantCulture); }

    // Returns the number of renderers exported.
    public static int Write(string gltfPath, string placementPath)
    {
        var bin = new List<byte>();
        var nodes = new StringBuilder();
        var meshes = new StringBuilder();
        var views = new StringBuilder();
        var accessors = new StringBuilder();
        var placements = new StringBuilder();
        var names = new HashSet<string>();
        int count = 0, view = 0;
        int pages = LightmapSettings.lightmaps.Length;
        foreach (var r in Object.FindObjectsOfType<MeshRenderer>())
        {
            // 0xFFFF: not lightmapped; 0xFFFE: lightmapped but not baked yet.
            if (r.lightmapIndex < 0 || r.lightmapIndex >= 0xFFFE || r.lightmapIndex >= pages) continue;
            var mf = r.GetComponent<MeshFilter>();
            if (mf == null || mf.sharedMesh == null) continue;
            Mesh mesh = mf.sharedMesh;
            if (!mesh.isReadable) { Debug.LogWarning($"ahdpack: {r.name}: mesh {mesh.name} is not readable (enable Read/Write)"); continue; }
            Vector3[] v = mesh.vertices, nrm = mesh.normals;
            var uvs = new List<Vector2>();
            mesh.GetUVs(1, uvs);  // Mesh.uv2, the lightmap UVs
            if (uvs.Count != v.Length) mesh.GetUVs(0, uvs);  // Unity falls back to uv when uv2 is absent
            if (uvs.Count != v.Length) { Debug.LogWarning($"ahdpack: {r.name}: no UVs"); continue; }
            Matrix4x4 m = r.transform.localToWorldMatrix, nm = m.inverse.transpose;
            // A unique node name: the GameObject's, with " #k" when another renderer has it.
            string name = r.gameObject.name;
            for (int k = 2; names.Contains(name); ++k) name = r.gameObject.name + " #" + k;
            names.Add(name);

            var pos = new List<float>(); var nor = new List<float>(); var tex = new List<float>(); var idx = new List<uint>();
            Vector3 lo = Vector3.positiveInfinity, hi = Vector3.negativeInfinity;
            for (int i = 0; i < v.Length; ++i)
            {
                Vector3 p = m.MultiplyPoint3x4(v[i]);
                p.x = -p.x;
                lo = Vector3.Min(lo, p); hi = Vector3.Max(hi, p);
                pos.Add(p.x); pos.Add(p.y); pos.Add(p.z);
                Vector3 q = nrm.Length == v.Length ? nm.MultiplyVector(nrm[i]).normalized : Vector3.zero;
                nor.Add(-q.x); nor.Add(q.y); nor.Add(q.z);
                tex.Add(uvs[i].x); tex.Add(1 - uvs[i].y);
            }
            for (int s = 0; s < mesh.subMeshCount; ++s)
            {
                if (mesh.GetTopology(s) != MeshTopology.Triangles) continue;
                int[] t = mesh.GetTriangles(s);
                for (int i = 0; i + 2 < t.Length; i += 3) { idx.Add((uint)t[i]); idx.Add((uint)t[i + 2]); idx.Add((uint)t[i + 1]); }
            }
            if (idx.Count == 0) continue;
            int a0 = view;
            AddView(bin, views, ref view, pos); AddView(bin, views, ref view, nor); AddView(bin, views, ref view, tex);
            AddIndexView(bin, views, ref view, idx);
            if (accessors.Length > 0) accessors.Append(',');
            accessors.Append($"{{\"bufferView\":{a0},\"componentType\":5126,\"count\":{v.Length},\"type\":\"VEC3\",\"min\":[{F(lo.x)},{F(lo.y)},{F(lo.z)}],\"max\":[{F(hi.x)},{F(hi.y)},{F(hi.z)}]}},");
            accessors.Append($"{{\"bufferView\":{a0 + 1},\"componentType\":5126,\"count\":{v.Length},\"type\":\"VEC3\"}},");
            accessors.Append($"{{\"bufferView\":{a0 + 2},\"componentType\":5126,\"count\":{v.Length},\"type\":\"VEC2\"}},");
            accessors.Append($"{{\"bufferView\":{a0 + 3},\"componentType\":5125,\"count\":{idx.Count},\"type\":\"SCALAR\"}}");
            if (count > 0) { nodes.Append(','); meshes.Append(','); placements.Append(','); }
            string json = name.Replace("\\", "\\\\").Replace("\"", "\\\"");
            nodes.Append($"{{\"name\":\"{json}\",\"mesh\":{count}}}");
            // TEXCOORD_0 and TEXCOORD_1 both hold the lightmap UVs: ahdpack's default set is the second.
            meshes.Append($"{{\"name\":\"{Esc(mesh.name)}\",\"primitives\":[{{\"attributes\":{{\"POSITION\":{a0},\"NORMAL\":{a0 + 1},\"TEXCOORD_0\":{a0 + 2},\"TEXCOORD_1\":{a0 + 2}}},\"indices\":{a0 + 3}}}]}}");
            Vector4 so = r.lightmapScaleOffset;
            placements.Append($"\n  {{\"node\": \"{json}\", \"page\": {r.lightmapIndex}, \"scale\": [{F(so.x)}, {F(so.y)}], \"offset\": [{F(so.z)}, {F(so.w)}]}}");
            ++count;
        }
        var sb = new StringBuilder();
        sb.Append("{\"asset\":{\"version\":\"2.0\",\"generator\":\"ahdpack AhdpackLightmapExport.cs\"},\"scene\":0,\"scenes\":[{\"nodes\":[");
        for (int i = 0; i < count; ++i) sb.Append(i > 0 ? "," : "").Append(i);
        sb.Append("]}],\"nodes\":[").Append(nodes).Append("],\"meshes\":[").Append(meshes).Append("],");
        sb.Append($"\"buffers\":[{{\"byteLength\":{bin.Count},\"uri\":\"data:application/octet-stream;base64,{System.Convert.ToBase64String(bin.ToArray())}\"}}],");
        sb.Append("\"bufferViews\":[").Append(views).Append("],\"accessors\":[").Append(accessors).Append("]}");
        File.WriteAllText(gltfPath, sb.ToString());
        File.WriteAllText(placementPath, "{\"placements\": [" + placements + "\n]}\n");
        return count;
    }

    static string Esc(string s) { return s.Replace("\\", "\\\\").Replace("\"", "\\\""); }

    static void AddView(List<byte> bin, StringBuilder views, ref int view, List<float> data)
    {
        while (bin.Count % 4 != 0) bin.Add(0);
        int start = bin.Count;
        foreach (float f in data) bin.AddRange(System.BitConverter.GetBytes(f));
        if (views.Length > 0) views.Append(',');
        views.Append($"{{\"buffer\":0,\"byteOffset\":{start},\"byteLength\":{bin.Count - start}}}");
        ++view;
    }

    static void AddIndexView(List<byte> bin, StringBuilder views, ref int view, List<uint> data)
    {
        while (bin.Count % 4 != 0) bin.Add(0);
        int start = bin.Count;
        foreach (uint u in data) bin.AddRange(System.BitConverter.GetBytes(u));
        if (views.Length > 0) views.Append(',');
        views.Append($"{{\"buffer\":0,\"byteOffset\":{start},\"byteLength\":{bin.Count - start}}}");
        ++view;
    }
}
#endif
