//! Writing a [`CurvedMesh`] (spec §5.3): Gmsh MSH 4.1 with high-order triangles, legacy VTK
//! with Lagrange triangles, and an OBJ preview of linear triangles. MSH and VTK carry each
//! element's smallest metric angle and region as data.
//!
//! Lagrange nodes are interpolation points at equispaced reference positions, in the order
//! of [`super::lagrange_layout`] — Gmsh's and VTK's for triangles (spec §5.3 [MEASURED]:
//! writing control points instead moves a cubic edge by up to 0.094 of its chord).

use std::fmt::Write as _;
use std::path::Path;

use glam::DVec3;

use super::output::CurvedMesh;
use crate::error::{Error, Result};

/// Which coordinates a file gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Space {
    /// On the surface: `P(u, v)` of every node.
    #[default]
    Surface,
    /// In the parameter square, `(u, v, 0)` (the exact curved elements of spec §5.2's `Uv`
    /// mode).
    Parameter,
}

/// Gmsh's element type of a triangle of order `q` (1 to 10; spec §5.3).
pub fn gmsh_triangle_type(q: u32) -> Option<u32> {
    Some(match q {
        1 => 2,
        2 => 9,
        3 => 21,
        4 => 23,
        5 => 25,
        6 => 42,
        7 => 43,
        8 => 44,
        9 => 45,
        10 => 46,
        _ => return None,
    })
}

impl CurvedMesh {
    fn node_position(&self, n: usize, space: Space) -> DVec3 {
        match space {
            Space::Surface => self.nodes_xyz[n],
            Space::Parameter => self.nodes_uv[n].extend(0.0),
        }
    }

    /// The linear preview: every element cut into `q²` flat triangles through its nodes
    /// (its curved edge is sampled at them). Node indices as in [`Self::nodes_xyz`];
    /// returns the triangles and, for each, its element.
    pub fn preview_triangles(&self) -> (Vec<[u32; 3]>, Vec<u32>) {
        let q = self.order;
        let layout = super::lagrange_layout(q);
        // Position in the layout of lattice point (a, b).
        let mut at = vec![0usize; ((q + 1) * (q + 1)) as usize];
        for (k, &[a, b]) in layout.iter().enumerate() {
            at[(a * (q + 1) + b) as usize] = k;
        }
        let idx = |a: u32, b: u32| at[(a * (q + 1) + b) as usize];
        let mut tris = Vec::with_capacity(self.element_count() * (q * q) as usize);
        let mut owner = Vec::with_capacity(tris.capacity());
        for e in 0..self.element_count() {
            let n = self.element(e);
            for a in 0..q {
                for b in 0..q - a {
                    tris.push([n[idx(a, b)], n[idx(a + 1, b)], n[idx(a, b + 1)]]);
                    owner.push(e as u32);
                    if a + b + 1 < q {
                        tris.push([n[idx(a + 1, b)], n[idx(a + 1, b + 1)], n[idx(a, b + 1)]]);
                        owner.push(e as u32);
                    }
                }
            }
        }
        (tris, owner)
    }

    /// The mesh as Gmsh MSH 4.1 (ASCII): one surface entity per region, high-order
    /// triangles of the mesh's order, and `$ElementData` views "min metric angle (deg)" (in
    /// the metric of each element's vertices) and "region".
    pub fn to_msh(&self, space: Space) -> Result<String> {
        let q = self.order;
        let ty = gmsh_triangle_type(q).ok_or_else(|| Error::InvalidOption {
            option: "order",
            message: format!("{q}: Gmsh triangles go up to order 10"),
        })?;
        let regions: Vec<u32> = {
            let mut r: Vec<u32> = self.info.iter().map(|i| i.region.0).collect();
            r.sort_unstable();
            r.dedup();
            r
        };
        let entity = |region: u32| regions.binary_search(&region).map(|i| i + 1).unwrap_or(1);
        // Each node is listed once, in the block of the first region that uses it.
        let mut node_entity = vec![usize::MAX; self.nodes_uv.len()];
        for (e, info) in self.info.iter().enumerate() {
            let ent = entity(info.region.0);
            for &n in self.element(e) {
                let slot = &mut node_entity[n as usize];
                *slot = (*slot).min(ent);
            }
        }
        let mut s = String::new();
        s.push_str("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
        // Entities: one surface per region with its nodes' bounding box.
        s.push_str("$Entities\n");
        let _ = writeln!(s, "0 0 {} 0", regions.len());
        for (i, _) in regions.iter().enumerate() {
            let mut lo = DVec3::splat(f64::INFINITY);
            let mut hi = DVec3::splat(f64::NEG_INFINITY);
            for (n, &ent) in node_entity.iter().enumerate() {
                if ent == i + 1 {
                    let p = self.node_position(n, space);
                    lo = lo.min(p);
                    hi = hi.max(p);
                }
            }
            if !lo.x.is_finite() {
                lo = DVec3::ZERO;
                hi = DVec3::ZERO;
            }
            let _ = writeln!(
                s,
                "{} {} {} {} {} {} {} 0 0",
                i + 1,
                lo.x,
                lo.y,
                lo.z,
                hi.x,
                hi.y,
                hi.z
            );
        }
        s.push_str("$EndEntities\n");
        // Nodes, by entity.
        let n_nodes = self.nodes_uv.len();
        s.push_str("$Nodes\n");
        let used: Vec<usize> = (1..=regions.len())
            .filter(|&ent| node_entity.contains(&ent))
            .collect();
        let _ = writeln!(s, "{} {} 1 {}", used.len(), n_nodes, n_nodes);
        for &ent in &used {
            let nodes: Vec<usize> = (0..n_nodes).filter(|&n| node_entity[n] == ent).collect();
            let _ = writeln!(s, "2 {ent} 0 {}", nodes.len());
            for &n in &nodes {
                let _ = writeln!(s, "{}", n + 1);
            }
            for &n in &nodes {
                let p = self.node_position(n, space);
                let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
            }
        }
        s.push_str("$EndNodes\n");
        // Elements, by region.
        let m = self.element_count();
        s.push_str("$Elements\n");
        let _ = writeln!(s, "{} {} 1 {}", regions.len(), m, m);
        for (i, &r) in regions.iter().enumerate() {
            let elems: Vec<usize> = (0..m).filter(|&e| self.info[e].region.0 == r).collect();
            let _ = writeln!(s, "2 {} {ty} {}", i + 1, elems.len());
            for e in elems {
                let _ = write!(s, "{}", e + 1);
                for &n in self.element(e) {
                    let _ = write!(s, " {}", n + 1);
                }
                s.push('\n');
            }
        }
        s.push_str("$EndElements\n");
        for (name, value) in [
            (
                "min metric angle (deg)",
                &(|e: usize| self.info[e].quality.min_angle_vertex) as &dyn Fn(usize) -> f64,
            ),
            ("region", &|e: usize| self.info[e].region.0 as f64),
        ] {
            let _ = writeln!(s, "$ElementData\n1\n\"{name}\"\n1\n0\n3\n0\n1\n{m}");
            for e in 0..m {
                let _ = writeln!(s, "{} {}", e + 1, value(e));
            }
            s.push_str("$EndElementData\n");
        }
        Ok(s)
    }

    /// The mesh as a legacy VTK unstructured grid: Lagrange triangles (cell type 69; plain
    /// triangles, type 5, at order 1) with cell data `min_metric_angle_deg`, `region` and
    /// `curved`.
    pub fn to_vtk(&self, space: Space) -> String {
        let q = self.order;
        let n = self.nodes_per_element();
        let m = self.element_count();
        let mut s = String::new();
        let _ = writeln!(
            s,
            "# vtk DataFile Version 4.2\nkatachi curved mesh (seed 000), order {q}, {}\nASCII\nDATASET UNSTRUCTURED_GRID",
            match space {
                Space::Surface => "on the surface",
                Space::Parameter => "in the parameter square",
            }
        );
        let _ = writeln!(s, "POINTS {} double", self.nodes_uv.len());
        for k in 0..self.nodes_uv.len() {
            let p = self.node_position(k, space);
            let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
        }
        let _ = writeln!(s, "CELLS {m} {}", m * (n + 1));
        for e in 0..m {
            let _ = write!(s, "{n}");
            for &v in self.element(e) {
                let _ = write!(s, " {v}");
            }
            s.push('\n');
        }
        let _ = writeln!(s, "CELL_TYPES {m}");
        let ty = if q == 1 { 5 } else { 69 };
        for _ in 0..m {
            let _ = writeln!(s, "{ty}");
        }
        let _ = writeln!(s, "CELL_DATA {m}");
        s.push_str("SCALARS min_metric_angle_deg double 1\nLOOKUP_TABLE default\n");
        for i in &self.info {
            let _ = writeln!(s, "{}", i.quality.min_angle_vertex);
        }
        s.push_str("SCALARS region int 1\nLOOKUP_TABLE default\n");
        for i in &self.info {
            let _ = writeln!(s, "{}", i.region.0);
        }
        s.push_str("SCALARS curved int 1\nLOOKUP_TABLE default\n");
        for i in &self.info {
            let _ = writeln!(s, "{}", (i.kind == super::ElementKind::Curved) as u8);
        }
        s
    }

    /// The linear preview ([`Self::preview_triangles`]) as OBJ, one group per region.
    pub fn to_obj_preview(&self, space: Space) -> String {
        let (tris, owner) = self.preview_triangles();
        let mut s = String::from("# katachi curved mesh (seed 000): linear preview\n");
        for k in 0..self.nodes_uv.len() {
            let p = self.node_position(k, space);
            let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
        }
        let mut current = u32::MAX;
        for (t, e) in tris.iter().zip(&owner) {
            let r = self.info[*e as usize].region.0;
            if r != current {
                let _ = writeln!(s, "g region_{r}");
                current = r;
            }
            let _ = writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        s
    }

    /// Writes the mesh to `path`, its format by extension: `.msh` (Gmsh 4.1), `.vtk` (legacy
    /// VTK) or `.obj` (linear preview). Written through a temporary file, so a failure leaves
    /// no half-written file.
    pub fn write(&self, path: &Path, space: Space) -> Result<()> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let text = match ext.as_deref() {
            Some("msh") => self.to_msh(space)?,
            Some("vtk") => self.to_vtk(space),
            Some("obj") => self.to_obj_preview(space),
            _ => {
                return Err(Error::InvalidArgument(format!(
                    "{}: unknown format for a curved mesh (use .msh, .vtk or .obj)",
                    path.display()
                )))
            }
        };
        crate::io::write_bytes(path, text.as_bytes())
    }
}
