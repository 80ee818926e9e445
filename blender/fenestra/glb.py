"""Binary glTF (.glb) files read and written whole: a JSON document and its binary chunk."""

import json
import struct

# "glTF", the first word of a .glb; the chunk types.
MAGIC, JSON_CHUNK, BIN_CHUNK = 0x46546C67, 0x4E4F534A, 0x004E4942


def read(path):
    """The file's version, JSON document and binary chunk (bytes, empty if none)."""
    with open(path, "rb") as f:
        data = f.read()
    magic, version, _ = struct.unpack_from("<III", data, 0)
    if magic != MAGIC:
        raise RuntimeError(f"{path} is not a binary glTF file")
    json_len, _ = struct.unpack_from("<II", data, 12)
    doc = json.loads(data[20 : 20 + json_len])
    at = 20 + json_len
    bin_len = struct.unpack_from("<I", data, at)[0] if at < len(data) else 0
    return version, doc, bytes(data[at + 8 : at + 8 + bin_len])


def write(path, version, doc, blob):
    """Writes a .glb of `doc` and `blob`, each chunk padded to 4 bytes."""
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    blob = bytes(blob) + b"\0" * (-len(blob) % 4)
    total = 12 + 8 + len(text) + 8 + len(blob)
    with open(path, "wb") as f:
        f.write(struct.pack("<III", MAGIC, version, total))
        f.write(struct.pack("<II", len(text), JSON_CHUNK) + text)
        f.write(struct.pack("<II", len(blob), BIN_CHUNK) + blob)
