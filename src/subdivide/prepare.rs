//! The mesh that level 0 refines, made from the caller's: faces with holes checked,
//! optionally recovered from coplanar regions and creased by feature angle, and bridged by
//! method `[a]` (seed 001 §4) where possible. Keeps the maps back to the caller's vertices,
//! faces and corners so that every attribute still refers to the caller's mesh.

use std::collections::HashMap;

use super::options::{HoleMethod, SubdivideOptions};
use super::regions::merge_coplanar_regions;
use super::tag_feature_edges;
use super::SubdivideReport;
use crate::error::Result;
use crate::mesh::holes::{bridge_face, validate_faces_with_holes};
use crate::mesh::{FaceId, LoopId, PolyMesh};

/// Level 0's mesh and its maps to the input. `None` maps are the identity.
#[derive(Debug, Clone)]
pub(crate) struct Prepared {
    /// `None` when the input is refined as it is.
    pub mesh: Option<PolyMesh>,
    pub vertex_origin: Option<Vec<u32>>,
    pub face_origin: Option<Vec<u32>>,
    pub corner_origin: Option<Vec<u32>>,
    /// Per level-0 face: the vertices whose average is its face point (method `[a]`).
    pub face_points: Vec<Option<Vec<u32>>>,
}

impl Prepared {
    /// Level 0 is the input itself, with no maps.
    pub fn identity() -> Prepared {
        Prepared {
            mesh: None,
            vertex_origin: None,
            face_origin: None,
            corner_origin: None,
            face_points: Vec::new(),
        }
    }

    pub fn mesh<'a>(&'a self, input: &'a PolyMesh) -> &'a PolyMesh {
        self.mesh.as_ref().unwrap_or(input)
    }
}

pub(crate) fn prepare(
    input: &PolyMesh,
    options: &SubdivideOptions,
    report: &mut SubdivideReport,
) -> Result<Prepared> {
    let mut p = Prepared {
        mesh: None,
        vertex_origin: None,
        face_origin: None,
        corner_origin: None,
        face_points: Vec::new(),
    };
    if options.recover_faces_with_holes {
        let merged = merge_coplanar_regions(input, &options.merge)?;
        let vertex_origin: Vec<u32> = merged.vertex_origin().iter().map(|v| v.0).collect();
        // A merged face's corner comes from a corner of one of its region's faces at the
        // same vertex (the lowest).
        let mut at: HashMap<(u32, u32), u32> = HashMap::new();
        for (g, faces) in merged.face_origin.iter().enumerate() {
            for &f in faces {
                for l in input.face_loops(f) {
                    let first = input.loop_first_corner(l);
                    for (k, v) in input.loop_vertices(l).iter().enumerate() {
                        at.entry((g as u32, v.0)).or_insert(first + k as u32);
                    }
                }
            }
        }
        let m = &merged.mesh;
        let mut corner_origin = Vec::with_capacity(m.corner_count() as usize);
        for g in m.faces() {
            for l in m.face_loops(g) {
                for v in m.loop_vertices(l) {
                    corner_origin.push(at[&(g.0, vertex_origin[v.idx()])]);
                }
            }
        }
        p.face_origin = Some(merged.face_origin.iter().map(|fs| fs[0].0).collect());
        p.vertex_origin = Some(vertex_origin);
        p.corner_origin = Some(corner_origin);
        p.mesh = Some(merged.mesh);
    }
    if let Some(angle) = options.feature_angle {
        p.mesh = Some(tag_feature_edges(p.mesh(input), angle)?);
    }
    let mesh = p.mesh(input);
    if mesh.faces().any(|f| mesh.face_loop_count(f) > 1) {
        validate_faces_with_holes(mesh)?;
        if options.holes == HoleMethod::Smooth {
            bridge(&mut p, input, report)?;
        }
    }
    Ok(p)
}

/// Method `[a]`: replaces each face with holes by its bridged virtual faces; faces that cannot
/// be bridged stay whole (method `[b]`) and are reported.
fn bridge(p: &mut Prepared, input: &PolyMesh, report: &mut SubdivideReport) -> Result<()> {
    let mesh = p.mesh(input);
    let mut faces: Vec<Vec<Vec<u32>>> = Vec::with_capacity(mesh.face_count() as usize);
    let mut face_points = Vec::with_capacity(mesh.face_count() as usize);
    let mut face_origin = Vec::with_capacity(mesh.face_count() as usize);
    let mut corner_origin = Vec::with_capacity(mesh.corner_count() as usize);
    let prev_face = |f: FaceId| p.face_origin.as_ref().map_or(f.0, |o| o[f.idx()]);
    let prev_corner = |k: u32| p.corner_origin.as_ref().map_or(k, |o| o[k as usize]);
    for f in mesh.faces() {
        let loops: Vec<LoopId> = mesh.face_loops(f).collect();
        let bridged = if loops.len() > 1 {
            match bridge_face(mesh, f) {
                Ok(b) => Some(b),
                Err(why) => {
                    report
                        .fell_back_to_sharp
                        .push((FaceId(prev_face(f)), why.to_string()));
                    None
                }
            }
        } else {
            None
        };
        match bridged {
            Some(b) => {
                // Loop vertices are distinct across the face's loops, so a vertex names its corner.
                let mut corner_of: HashMap<u32, u32> = HashMap::new();
                for &l in &loops {
                    let first = mesh.loop_first_corner(l);
                    for (k, v) in mesh.loop_vertices(l).iter().enumerate() {
                        corner_of.insert(v.0, first + k as u32);
                    }
                }
                for (vf, fp) in b.faces.iter().zip(&b.face_point_vertices) {
                    faces.push(vec![vf.iter().map(|v| v.0).collect()]);
                    face_points.push(Some(fp.iter().map(|v| v.0).collect()));
                    face_origin.push(prev_face(f));
                    corner_origin.extend(vf.iter().map(|v| prev_corner(corner_of[&v.0])));
                }
            }
            None => {
                faces.push(
                    loops
                        .iter()
                        .map(|&l| mesh.loop_vertices(l).iter().map(|v| v.0).collect())
                        .collect(),
                );
                face_points.push(None);
                face_origin.push(prev_face(f));
                for &l in &loops {
                    let first = mesh.loop_first_corner(l);
                    let n = mesh.loop_vertices(l).len() as u32;
                    corner_origin.extend((first..first + n).map(prev_corner));
                }
            }
        }
    }
    let mut out = PolyMesh::from_faces_with_holes(mesh.positions().to_vec(), faces)?;
    out.set_edge_sharpnesses(mesh.sharp_edges().collect::<Vec<_>>())?;
    out.set_all_vertex_sharpness(mesh.vertex_sharpness().to_vec())?;
    p.mesh = Some(out);
    p.face_origin = Some(face_origin);
    p.corner_origin = Some(corner_origin);
    p.face_points = face_points;
    Ok(())
}
