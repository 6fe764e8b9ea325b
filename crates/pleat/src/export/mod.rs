//! Writers for simulated meshes: OBJ sequences, PLY and animated binary glTF.
