//! Triangle meshes as ASCII PLY (Turk 1994), the mesh format Mitsuba 3 and pbrt-v4 both
//! read: `vertex` x, y, z as doubles in full precision, `face` vertex index lists, the
//! winding kept (the front side is where (p₁ − p₀) × (p₂ − p₀) points, in every renderer
//! here).

use super::num;
use glam::DVec3;

/// The PLY text of a mesh.
pub fn ascii(vertices: &[DVec3], faces: &[[u32; 3]]) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\ncomment written by lightproof export\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        vertices.len(),
        faces.len()
    );
    for v in vertices {
        s.push_str(&format!("{} {} {}\n", num(v.x), num(v.y), num(v.z)));
    }
    for f in faces {
        s.push_str(&format!("3 {} {} {}\n", f[0], f[1], f[2]));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_counts_match_the_body() {
        let t = ascii(&[DVec3::ZERO, DVec3::X, DVec3::Y], &[[0, 1, 2]]);
        assert!(t.contains("element vertex 3\n") && t.contains("element face 1\n"));
        assert!(
            t.ends_with("end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
            "{t}"
        );
    }
}
