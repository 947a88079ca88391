//! JSON schemas of the messages a recording holds: Foxglove's well-known message types by
//! name (`foxglove.FrameTransforms`, `foxglove.SceneUpdate`), described here for the fields
//! corps writes, and corps' own signal rows.

/// `foxglove.FrameTransforms`: transforms between named frames.
pub const FRAME_TRANSFORMS: &str = r##"{
  "title": "foxglove.FrameTransforms", "type": "object",
  "properties": {"transforms": {"type": "array", "items": {"type": "object", "properties": {
    "timestamp": {"$ref": "#/$defs/time"},
    "parent_frame_id": {"type": "string"}, "child_frame_id": {"type": "string"},
    "translation": {"$ref": "#/$defs/vector3"}, "rotation": {"$ref": "#/$defs/quaternion"}}}}},
  "$defs": {
    "time": {"type": "object", "properties": {"sec": {"type": "integer"}, "nsec": {"type": "integer"}}},
    "vector3": {"type": "object", "properties": {"x": {"type": "number"}, "y": {"type": "number"}, "z": {"type": "number"}}},
    "quaternion": {"type": "object", "properties": {"x": {"type": "number"}, "y": {"type": "number"}, "z": {"type": "number"}, "w": {"type": "number"}}}}
}"##;

/// `foxglove.SceneUpdate`: entities (meshes, primitives, arrows, lines) in frames.
pub const SCENE_UPDATE: &str = r##"{
  "title": "foxglove.SceneUpdate", "type": "object",
  "properties": {
    "deletions": {"type": "array", "items": {"type": "object"}},
    "entities": {"type": "array", "items": {"type": "object", "properties": {
      "timestamp": {"type": "object"}, "frame_id": {"type": "string"}, "id": {"type": "string"},
      "lifetime": {"type": "object"}, "frame_locked": {"type": "boolean"},
      "metadata": {"type": "array"}, "arrows": {"type": "array"}, "cubes": {"type": "array"},
      "spheres": {"type": "array"}, "cylinders": {"type": "array"}, "lines": {"type": "array"},
      "triangles": {"type": "array"}, "texts": {"type": "array"}, "models": {"type": "array",
        "items": {"type": "object", "properties": {
          "pose": {"type": "object"}, "scale": {"type": "object"}, "color": {"type": "object"},
          "override_color": {"type": "boolean"}, "url": {"type": "string"},
          "media_type": {"type": "string"},
          "data": {"type": "string", "contentEncoding": "base64"}}}}}}}}
}"##;

/// `corps.Signals`: one row of the run's log, column name → value (SI units, the log's).
pub const SIGNALS: &str = r##"{
  "title": "corps.Signals", "type": "object",
  "additionalProperties": {"type": "number"}
}"##;
