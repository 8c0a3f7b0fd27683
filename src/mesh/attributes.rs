//! Per-element attributes of a [`PolyMesh`]: sharpness (OpenSubdiv semantics), selections, labels.
//!
//! Sharpness follows OpenSubdiv: 0 is smooth, values in (0, 10) are semi-sharp (the crease
//! relaxes after that many levels), and ≥ 10 ([`INFINITELY_SHARP`]) is infinitely sharp.
//! Edge sharpness is sparse (creases are few), keyed by the undirected vertex pair and kept
//! in a `BTreeMap` so iteration order, and hence every output, is deterministic.

use std::collections::BTreeMap;

use super::ids::{FaceId, VertexId};
use super::polymesh::PolyMesh;
use crate::error::{Error, Result};

/// Sharpness at or above which OpenSubdiv treats an edge or vertex as infinitely sharp.
pub const INFINITELY_SHARP: f64 = 10.0;

#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct Attributes {
    /// Key `(min, max)` vertex pair; only values > 0 are stored.
    pub(crate) edge_sharpness: BTreeMap<(u32, u32), f64>,
    pub(crate) vertex_sharpness: Vec<f64>,
    pub(crate) vertex_selection: Vec<bool>,
    pub(crate) face_selection: Vec<bool>,
    pub(crate) face_labels: Vec<u32>,
}

impl Attributes {
    pub(crate) fn new(vertices: usize, faces: usize) -> Self {
        Attributes {
            edge_sharpness: BTreeMap::new(),
            vertex_sharpness: vec![0.0; vertices],
            vertex_selection: vec![false; vertices],
            face_selection: vec![false; faces],
            face_labels: vec![0; faces],
        }
    }
}

fn edge_key(a: VertexId, b: VertexId) -> (u32, u32) {
    (a.0.min(b.0), a.0.max(b.0))
}

fn check_sharpness(element: impl FnOnce() -> String, value: f64) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidSharpness {
            element: element(),
            value,
        })
    }
}

fn check_len(
    attribute: &'static str,
    per: &'static str,
    expected: usize,
    got: usize,
) -> Result<()> {
    if expected == got {
        Ok(())
    } else {
        Err(Error::AttributeLength {
            attribute,
            per,
            expected,
            got,
        })
    }
}

impl PolyMesh {
    /// Which of the `keys` (sorted `(min, max)` vertex pairs) are sides of some loop: one
    /// pass over the corners, looking up only those at a key's smaller vertex (a few creases
    /// on a large mesh cost a pass, not a set of every edge).
    fn find_edges(&self, keys: &[(u32, u32)]) -> Vec<bool> {
        debug_assert!(keys.is_sorted());
        let mut found = vec![false; keys.len()];
        if keys.is_empty() {
            return found;
        }
        let mut at_end = vec![false; self.vertex_count() as usize];
        for &(a, _) in keys {
            if let Some(x) = at_end.get_mut(a as usize) {
                *x = true;
            }
        }
        let corners = self.corners();
        for w in self.loop_offsets().windows(2) {
            let (a, b) = (w[0] as usize, w[1] as usize);
            for c in a..b {
                let key = edge_key(corners[c], corners[if c + 1 < b { c + 1 } else { a }]);
                if at_end[key.0 as usize] {
                    if let Ok(i) = keys.binary_search(&key) {
                        found[i] = true;
                    }
                }
            }
        }
        found
    }

    /// Sharpness of the edge between `a` and `b` (0 when none was set).
    pub fn edge_sharpness(&self, a: VertexId, b: VertexId) -> f64 {
        self.attributes
            .edge_sharpness
            .get(&edge_key(a, b))
            .copied()
            .unwrap_or(0.0)
    }

    /// Edges with sharpness > 0, sorted by `(min vertex, max vertex)`.
    pub fn sharp_edges(&self) -> impl ExactSizeIterator<Item = (VertexId, VertexId, f64)> + '_ {
        self.attributes
            .edge_sharpness
            .iter()
            .map(|(&(a, b), &s)| (VertexId(a), VertexId(b), s))
    }

    /// Sets one edge's sharpness. The edge must exist; 0 makes it smooth again.
    pub fn set_edge_sharpness(&mut self, a: VertexId, b: VertexId, sharpness: f64) -> Result<()> {
        self.set_edge_sharpnesses([(a, b, sharpness)])
    }

    /// Sets many edges' sharpness at once (one pass to learn the edges). All or nothing: on
    /// an error no value is changed.
    pub fn set_edge_sharpnesses<I>(&mut self, values: I) -> Result<()>
    where
        I: IntoIterator<Item = (VertexId, VertexId, f64)>,
    {
        let values: Vec<_> = values.into_iter().collect();
        if values.is_empty() {
            return Ok(());
        }
        let mut keys: Vec<(u32, u32)> = values.iter().map(|&(a, b, _)| edge_key(a, b)).collect();
        keys.sort_unstable();
        keys.dedup();
        let found = self.find_edges(&keys);
        for &(a, b, s) in &values {
            let i = keys.binary_search(&edge_key(a, b)).expect("every key");
            if !found[i] {
                return Err(Error::NoSuchEdge { a: a.0, b: b.0 });
            }
            check_sharpness(|| format!("edge {a}-{b}"), s)?;
        }
        for (a, b, s) in values {
            if s > 0.0 {
                self.attributes.edge_sharpness.insert(edge_key(a, b), s);
            } else {
                self.attributes.edge_sharpness.remove(&edge_key(a, b));
            }
        }
        Ok(())
    }

    /// Sets the sharpness of those of the given vertex pairs that are edges, all or nothing,
    /// and returns how many pairs are no side of any face (a host's loose edges, which
    /// [`PolyMesh::set_edge_sharpnesses`] refuses). Values as there: finite and ≥ 0.
    pub fn set_sharpness_of_existing_edges<I>(&mut self, values: I) -> Result<u32>
    where
        I: IntoIterator<Item = (VertexId, VertexId, f64)>,
    {
        let values: Vec<_> = values.into_iter().collect();
        for &(a, b, s) in &values {
            check_sharpness(|| format!("edge {a}-{b}"), s)?;
        }
        let mut keys: Vec<(u32, u32)> = values.iter().map(|&(a, b, _)| edge_key(a, b)).collect();
        keys.sort_unstable();
        keys.dedup();
        let found = self.find_edges(&keys);
        let mut skipped = 0;
        for (a, b, s) in values {
            let key = edge_key(a, b);
            if !found[keys.binary_search(&key).expect("every key")] {
                skipped += 1;
            } else if s > 0.0 {
                self.attributes.edge_sharpness.insert(key, s);
            } else {
                self.attributes.edge_sharpness.remove(&key);
            }
        }
        Ok(skipped)
    }

    /// Makes every edge smooth.
    pub fn clear_edge_sharpness(&mut self) {
        self.attributes.edge_sharpness.clear();
    }

    /// Vertex (corner) sharpness, #V.
    pub fn vertex_sharpness(&self) -> &[f64] {
        &self.attributes.vertex_sharpness
    }
    /// Sets one vertex's sharpness.
    pub fn set_vertex_sharpness(&mut self, v: VertexId, sharpness: f64) -> Result<()> {
        if v.0 >= self.vertex_count() {
            return Err(Error::InvalidArgument(format!(
                "vertex {v} is out of range (the mesh has {} vertices)",
                self.vertex_count()
            )));
        }
        check_sharpness(|| format!("vertex {v}"), sharpness)?;
        self.attributes.vertex_sharpness[v.idx()] = sharpness;
        Ok(())
    }
    /// Replaces all vertex sharpness values (#V).
    pub fn set_all_vertex_sharpness(&mut self, values: Vec<f64>) -> Result<()> {
        check_len(
            "vertex sharpness",
            "vertex",
            self.vertex_count() as usize,
            values.len(),
        )?;
        for (i, &s) in values.iter().enumerate() {
            check_sharpness(|| format!("vertex {i}"), s)?;
        }
        self.attributes.vertex_sharpness = values;
        Ok(())
    }

    /// Vertex selection, #V.
    pub fn vertex_selection(&self) -> &[bool] {
        &self.attributes.vertex_selection
    }
    /// Replaces the vertex selection (#V).
    pub fn set_vertex_selection(&mut self, values: Vec<bool>) -> Result<()> {
        check_len(
            "vertex selection",
            "vertex",
            self.vertex_count() as usize,
            values.len(),
        )?;
        self.attributes.vertex_selection = values;
        Ok(())
    }
    /// Face selection, #F.
    pub fn face_selection(&self) -> &[bool] {
        &self.attributes.face_selection
    }
    /// Replaces the face selection (#F).
    pub fn set_face_selection(&mut self, values: Vec<bool>) -> Result<()> {
        check_len(
            "face selection",
            "face",
            self.face_count() as usize,
            values.len(),
        )?;
        self.attributes.face_selection = values;
        Ok(())
    }
    /// Face labels, #F (0 by default).
    pub fn face_labels(&self) -> &[u32] {
        &self.attributes.face_labels
    }
    /// The label of one face.
    pub fn face_label(&self, f: FaceId) -> u32 {
        self.attributes.face_labels[f.idx()]
    }
    /// Replaces the face labels (#F).
    pub fn set_face_labels(&mut self, values: Vec<u32>) -> Result<()> {
        check_len(
            "face labels",
            "face",
            self.face_count() as usize,
            values.len(),
        )?;
        self.attributes.face_labels = values;
        Ok(())
    }
}
