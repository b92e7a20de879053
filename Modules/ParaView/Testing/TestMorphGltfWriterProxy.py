"""pvbatch test: the MorphNode glTF writer proxy (vtkMorphGltfWriter) in ParaView.

    pvbatch TestMorphGltfWriterProxy.py --plugin .../MorphNodePlugin.so

File > Save Data's way (CreateWriter by extension) picks the writer for .glb and .gltf;
the repository's default head (a whole head from the MorphNode Face Reader) with the
Behavior Time Source's whole track (its second port) on Performance, optimized, is written
with one animation: a weights channel per mesh with targets and rotation channels for the
head and both eyes; without a Performance the head is written alone as JSON.
"""
import json
import os
import shutil
import struct
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import morphnode_pvtest as t  # noqa: E402

REPOSITORY = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", ".."))
HEAD = os.path.join(REPOSITORY, "Data", "DefaultFace", "default_head.glb")


def glb_json(path):
    with open(path, "rb") as f:
        data = f.read()
    length = struct.unpack("<I", data[12:16])[0]
    return data[:4], json.loads(data[20:20 + length])


def run(c, args):
    from paraview import simple
    from paraview import servermanager as sm

    t.load_plugin(args.plugin, globals())
    out = tempfile.mkdtemp(prefix="morphnode-gltf-")
    head = MorphNodeFaceReader(FileName=HEAD)  # noqa: F821 - the whole head
    behavior = MorphNodeBehaviorTimeSource()  # noqa: F821
    behavior.Duration = 2.0

    glb = os.path.join(out, "head.glb")
    writer = simple.CreateWriter(glb, head)
    c.require(writer is not None and writer.GetXMLName() == "MorphGltfWriter",
              "CreateWriter picks the MorphNode glTF writer for .glb")
    writer.Performance = sm.OutputPort(behavior, 1)
    writer.ApplyOptimizer = 1
    writer.Threshold = 0.2
    writer.UpdatePipeline()
    c.require(os.path.isfile(glb), "the writer wrote %s" % glb)
    magic, doc = glb_json(glb)
    c.check(magic == b"glTF", "a GLB")
    animations = doc.get("animations", [])
    c.require(len(animations) == 1, "one animation")
    paths = [channel["target"]["path"] for channel in animations[0]["channels"]]
    with_targets = sum(1 for mesh in doc["meshes"] if "targetNames" in mesh.get("extras", {}))
    c.check(paths.count("weights") == with_targets and with_targets > 0,
            "a weights channel per mesh with targets (%d)" % with_targets)
    c.check(paths.count("rotation") == 3, "rotation channels: the head and both eyes (%d)" % paths.count("rotation"))
    times = doc["accessors"][animations[0]["samplers"][0]["input"]]
    c.check(times["count"] == 61, "the track's 61 frames (2 s at 30 fps): %d" % times["count"])

    gltf = os.path.join(out, "head.gltf")
    simple.SaveData(gltf, proxy=head)
    c.require(os.path.isfile(gltf), "SaveData wrote %s" % gltf)
    with open(gltf) as f:
        doc = json.load(f)
    c.check("animations" not in doc and len(doc["meshes"]) == 11,
            "without a Performance: the head alone (11 meshes), no animation")
    shutil.rmtree(out, ignore_errors=True)


if __name__ == "__main__":
    arguments = t.common_arguments(__doc__.splitlines()[0]).parse_args()
    t.main(lambda c: run(c, arguments), "TestMorphGltfWriterProxy")
