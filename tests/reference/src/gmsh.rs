//! Gmsh 4.8 (Debian's libgmsh-dev) through its own C API, the peer for curved meshing
//! (seed 000): reading MSH files with Gmsh's own Jacobian check (`AnalyseMeshQuality`), and
//! meshing a trimmed parameter domain with Gmsh's anisotropic mesher, BAMG
//! (`Mesh.Algorithm = 7`), for a tensor metric given as a background view.
//!
//! Gmsh keeps global state, so every call takes a process-wide lock, initializes Gmsh and
//! finalizes it. Arrays Gmsh allocates are copied out and released with `gmshFree`.

use std::ffi::{c_char, c_int, CString};
use std::sync::Mutex;

#[allow(
    non_upper_case_globals,
    non_camel_case_types,
    non_snake_case,
    dead_code
)]
mod sys {
    include!(concat!(env!("OUT_DIR"), "/gmsh_bindings.rs"));
}

static LOCK: Mutex<()> = Mutex::new(());

/// An initialized Gmsh, finalized on drop; holds the lock.
struct Session {
    _guard: std::sync::MutexGuard<'static, ()>,
}

fn check(ierr: c_int, what: &str) -> Result<(), String> {
    if ierr == 0 {
        Ok(())
    } else {
        Err(format!("gmsh: {what} failed (ierr {ierr})"))
    }
}

fn cstr(s: &str) -> CString {
    CString::new(s).expect("no NUL in Gmsh names")
}

impl Session {
    fn new() -> Result<Self, String> {
        let guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        let mut ierr = 0;
        // SAFETY: argc 0 with a null argv is Gmsh's documented "no arguments".
        unsafe { sys::gmshInitialize(0, std::ptr::null_mut(), 0, &mut ierr) };
        check(ierr, "initialize")?;
        let s = Session { _guard: guard };
        s.number("General.Terminal", 0.0)?;
        s.number("General.Verbosity", 0.0)?;
        Ok(s)
    }

    fn number(&self, name: &str, value: f64) -> Result<(), String> {
        let mut ierr = 0;
        let n = cstr(name);
        unsafe { sys::gmshOptionSetNumber(n.as_ptr(), value, &mut ierr) };
        check(ierr, name)
    }

    fn plugin_number(&self, plugin: &str, option: &str, value: f64) -> Result<(), String> {
        let mut ierr = 0;
        let (p, o) = (cstr(plugin), cstr(option));
        unsafe { sys::gmshPluginSetNumber(p.as_ptr(), o.as_ptr(), value, &mut ierr) };
        check(ierr, option)
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        let mut ierr = 0;
        unsafe { sys::gmshFinalize(&mut ierr) };
    }
}

/// Copies a Gmsh-allocated array out and frees it.
unsafe fn take<T: Copy>(p: *mut T, n: usize) -> Vec<T> {
    if p.is_null() {
        return Vec::new();
    }
    let v = unsafe { std::slice::from_raw_parts(p, n) }.to_vec();
    unsafe { sys::gmshFree(p as *mut std::ffi::c_void) };
    v
}

/// A mesh as Gmsh read it.
#[derive(Debug, Clone, Default)]
pub struct MshContents {
    /// Node tags and coordinates.
    pub node_tags: Vec<usize>,
    pub node_coords: Vec<[f64; 3]>,
    /// Per element type (Gmsh's number): element tags and their node tags.
    pub elements: Vec<(i32, Vec<usize>, Vec<usize>)>,
    /// Per element (in the order of the `AnalyseMeshQuality` view): the ratio of the smallest
    /// to the largest Jacobian determinant Gmsh computes (its own validity check; > 0 valid).
    pub min_over_max_jacobian: Vec<(usize, f64)>,
}

/// Opens `path` in Gmsh, reads back its nodes and elements, and runs Gmsh's
/// `AnalyseMeshQuality` plugin (Jacobian determinant) on its triangles.
pub fn read_and_check_msh(path: &std::path::Path) -> Result<MshContents, String> {
    let s = Session::new()?;
    let mut ierr = 0;
    let p = cstr(&path.to_string_lossy());
    unsafe { sys::gmshOpen(p.as_ptr(), &mut ierr) };
    check(ierr, "open")?;
    let mut out = MshContents::default();
    unsafe {
        let (mut tags, mut nt) = (std::ptr::null_mut(), 0usize);
        let (mut coord, mut nc) = (std::ptr::null_mut(), 0usize);
        let (mut par, mut np) = (std::ptr::null_mut(), 0usize);
        sys::gmshModelMeshGetNodes(
            &mut tags, &mut nt, &mut coord, &mut nc, &mut par, &mut np, -1, -1, 0, 0, &mut ierr,
        );
        check(ierr, "getNodes")?;
        out.node_tags = take(tags, nt);
        let c = take(coord, nc);
        out.node_coords = c.chunks(3).map(|x| [x[0], x[1], x[2]]).collect();
        let _ = take(par, np);
        let (mut types, mut ntypes) = (std::ptr::null_mut(), 0usize);
        let (mut etags, mut etags_n, mut etags_nn) =
            (std::ptr::null_mut(), std::ptr::null_mut(), 0usize);
        let (mut enodes, mut enodes_n, mut enodes_nn) =
            (std::ptr::null_mut(), std::ptr::null_mut(), 0usize);
        sys::gmshModelMeshGetElements(
            &mut types,
            &mut ntypes,
            &mut etags,
            &mut etags_n,
            &mut etags_nn,
            &mut enodes,
            &mut enodes_n,
            &mut enodes_nn,
            2,
            -1,
            &mut ierr,
        );
        check(ierr, "getElements")?;
        let types = take(types, ntypes);
        let etag_lens = take(etags_n, etags_nn);
        let enode_lens = take(enodes_n, enodes_nn);
        let etag_ptrs = take(etags, etags_nn);
        let enode_ptrs = take(enodes, enodes_nn);
        for k in 0..types.len() {
            out.elements.push((
                types[k],
                take(etag_ptrs[k], etag_lens[k]),
                take(enode_ptrs[k], enode_lens[k]),
            ));
        }
    }
    s.plugin_number("AnalyseMeshQuality", "JacobianDeterminant", 1.0)?;
    s.plugin_number("AnalyseMeshQuality", "IGEMeasure", 0.0)?;
    s.plugin_number("AnalyseMeshQuality", "ICNMeasure", 0.0)?;
    s.plugin_number("AnalyseMeshQuality", "HidingThreshold", 1e10)?;
    s.plugin_number("AnalyseMeshQuality", "CreateView", 1.0)?;
    s.plugin_number("AnalyseMeshQuality", "DimensionOfElements", 2.0)?;
    let name = cstr("AnalyseMeshQuality");
    unsafe { sys::gmshPluginRun(name.as_ptr(), &mut ierr) };
    check(ierr, "AnalyseMeshQuality")?;
    // The plugin's view is the last one.
    unsafe {
        let (mut vt, mut nvt) = (std::ptr::null_mut(), 0usize);
        sys::gmshViewGetTags(&mut vt, &mut nvt, &mut ierr);
        check(ierr, "getTags")?;
        let views = take(vt, nvt);
        let view = *views
            .last()
            .ok_or("gmsh: AnalyseMeshQuality made no view")?;
        let mut data_type: *mut c_char = std::ptr::null_mut();
        let (mut tags, mut nt) = (std::ptr::null_mut(), 0usize);
        let (mut data, mut data_n, mut data_nn) =
            (std::ptr::null_mut(), std::ptr::null_mut(), 0usize);
        let (mut time, mut ncomp) = (0.0, 0);
        sys::gmshViewGetModelData(
            view,
            0,
            &mut data_type,
            &mut tags,
            &mut nt,
            &mut data,
            &mut data_n,
            &mut data_nn,
            &mut time,
            &mut ncomp,
            &mut ierr,
        );
        check(ierr, "getModelData")?;
        let _ = take(data_type, 0);
        let tags = take(tags, nt);
        let lens = take(data_n, data_nn);
        let ptrs = take(data, data_nn);
        for (k, t) in tags.iter().enumerate() {
            let v = take(ptrs[k], lens[k]);
            out.min_over_max_jacobian
                .push((*t, v.first().copied().unwrap_or(f64::NAN)));
        }
    }
    Ok(out)
}

/// One curve of a trimmed domain for Gmsh: Bézier control points in the plane (two for a
/// straight segment).
#[derive(Debug, Clone)]
pub struct PlaneCurve {
    pub points: Vec<[f64; 2]>,
}

/// A trimmed parameter domain and a metric on it, for Gmsh's BAMG.
#[derive(Debug, Clone)]
pub struct BamgInput {
    /// Loops of curves (each curve as traversed, consecutive ones sharing end points exactly);
    /// the first loop is the outer boundary.
    pub loops: Vec<Vec<PlaneCurve>>,
    /// The metric sampled on a regular `n × n` grid over the box `[lo, hi]`, row by row in v,
    /// each `[uu, uv, vv]`.
    pub lo: [f64; 2],
    pub hi: [f64; 2],
    pub grid: usize,
    pub metric: Vec<[f64; 3]>,
}

/// BAMG's mesh: vertices, triangles (both orientations possible) and the time Gmsh took to
/// generate it (`gmshModelMeshGenerate(2)`, boundary discretization included).
#[derive(Debug, Clone)]
pub struct BamgMesh {
    pub uv: Vec<[f64; 2]>,
    pub triangles: Vec<[u32; 3]>,
    pub seconds: f64,
}

/// Meshes `input` with Gmsh's anisotropic mesher BAMG: the curves as built-in Bézier curves,
/// one plane surface, the metric as a tensor background view (`TT` list data on the grid's
/// triangles, extended to 3D with the largest eigenvalue across the plane), mesh sizes only
/// from that view.
pub fn bamg(input: &BamgInput) -> Result<BamgMesh, String> {
    let s = Session::new()?;
    let mut ierr = 0;
    let model = cstr("bamg");
    unsafe { sys::gmshModelAdd(model.as_ptr(), &mut ierr) };
    check(ierr, "model add")?;
    let mut points: Vec<([u64; 2], c_int)> = Vec::new();
    let mut point = |p: [f64; 2]| -> Result<c_int, String> {
        let key = [p[0].to_bits(), p[1].to_bits()];
        if let Some((_, t)) = points.iter().find(|(k, _)| *k == key) {
            return Ok(*t);
        }
        let mut ierr = 0;
        let t = unsafe { sys::gmshModelGeoAddPoint(p[0], p[1], 0.0, 0.0, -1, &mut ierr) };
        check(ierr, "addPoint")?;
        points.push((key, t));
        Ok(t)
    };
    let mut wires = Vec::new();
    for lp in &input.loops {
        let mut curves = Vec::new();
        for c in lp {
            let mut tags: Vec<c_int> = Vec::with_capacity(c.points.len());
            for (k, &p) in c.points.iter().enumerate() {
                // Inner control points are never shared.
                if k == 0 || k + 1 == c.points.len() {
                    tags.push(point(p)?);
                } else {
                    let t =
                        unsafe { sys::gmshModelGeoAddPoint(p[0], p[1], 0.0, 0.0, -1, &mut ierr) };
                    check(ierr, "addPoint")?;
                    tags.push(t);
                }
            }
            let t = if tags.len() == 2 {
                unsafe { sys::gmshModelGeoAddLine(tags[0], tags[1], -1, &mut ierr) }
            } else {
                unsafe { sys::gmshModelGeoAddBezier(tags.as_mut_ptr(), tags.len(), -1, &mut ierr) }
            };
            check(ierr, "add curve")?;
            curves.push(t);
        }
        let w = unsafe {
            sys::gmshModelGeoAddCurveLoop(curves.as_mut_ptr(), curves.len(), -1, 0, &mut ierr)
        };
        check(ierr, "addCurveLoop")?;
        wires.push(w);
    }
    unsafe { sys::gmshModelGeoAddPlaneSurface(wires.as_mut_ptr(), wires.len(), -1, &mut ierr) };
    check(ierr, "addPlaneSurface")?;
    unsafe { sys::gmshModelGeoSynchronize(&mut ierr) };
    check(ierr, "synchronize")?;
    // The background view: the grid's cells as two triangles each, a 3×3 tensor per corner.
    let n = input.grid;
    let at = |i: usize, j: usize| -> ([f64; 2], [f64; 9]) {
        let u = input.lo[0] + (input.hi[0] - input.lo[0]) * i as f64 / (n - 1) as f64;
        let v = input.lo[1] + (input.hi[1] - input.lo[1]) * j as f64 / (n - 1) as f64;
        let m = input.metric[j * n + i];
        let zz = 0.5 * (m[0] + m[2]) + (0.25 * (m[0] - m[2]).powi(2) + m[1] * m[1]).sqrt();
        ([u, v], [m[0], m[1], 0.0, m[1], m[2], 0.0, 0.0, 0.0, zz])
    };
    let mut data = Vec::new();
    let mut count = 0;
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            for tri in [
                [(i, j), (i + 1, j), (i + 1, j + 1)],
                [(i, j), (i + 1, j + 1), (i, j + 1)],
            ] {
                let c: Vec<([f64; 2], [f64; 9])> = tri.iter().map(|&(a, b)| at(a, b)).collect();
                data.extend(c.iter().map(|x| x.0[0]));
                data.extend(c.iter().map(|x| x.0[1]));
                data.extend([0.0; 3]);
                for x in &c {
                    data.extend(x.1);
                }
                count += 1;
            }
        }
    }
    let vname = cstr("metric");
    let view = unsafe { sys::gmshViewAdd(vname.as_ptr(), -1, &mut ierr) };
    check(ierr, "viewAdd")?;
    let tt = cstr("TT");
    unsafe {
        sys::gmshViewAddListData(
            view,
            tt.as_ptr(),
            count,
            data.as_mut_ptr(),
            data.len(),
            &mut ierr,
        )
    };
    check(ierr, "addListData")?;
    let field_kind = cstr("PostView");
    let f = unsafe { sys::gmshModelMeshFieldAdd(field_kind.as_ptr(), -1, &mut ierr) };
    check(ierr, "fieldAdd")?;
    let vt = cstr("ViewTag");
    unsafe { sys::gmshModelMeshFieldSetNumber(f, vt.as_ptr(), view as f64, &mut ierr) };
    check(ierr, "ViewTag")?;
    unsafe { sys::gmshModelMeshFieldSetAsBackgroundMesh(f, &mut ierr) };
    check(ierr, "setAsBackgroundMesh")?;
    s.number("Mesh.Algorithm", 7.0)?;
    s.number("Mesh.AnisoMax", 1000.0)?;
    s.number("Mesh.MeshSizeExtendFromBoundary", 0.0)?;
    s.number("Mesh.MeshSizeFromPoints", 0.0)?;
    s.number("Mesh.MeshSizeFromCurvature", 0.0)?;
    let t0 = std::time::Instant::now();
    unsafe { sys::gmshModelMeshGenerate(2, &mut ierr) };
    let seconds = t0.elapsed().as_secs_f64();
    check(ierr, "generate")?;
    let mut out = BamgMesh {
        uv: Vec::new(),
        triangles: Vec::new(),
        seconds,
    };
    unsafe {
        let (mut tags, mut nt) = (std::ptr::null_mut(), 0usize);
        let (mut coord, mut nc) = (std::ptr::null_mut(), 0usize);
        let (mut par, mut np) = (std::ptr::null_mut(), 0usize);
        sys::gmshModelMeshGetNodes(
            &mut tags, &mut nt, &mut coord, &mut nc, &mut par, &mut np, -1, -1, 0, 0, &mut ierr,
        );
        check(ierr, "getNodes")?;
        let tags = take(tags, nt);
        let coord = take(coord, nc);
        let _ = take(par, np);
        let max = tags.iter().copied().max().unwrap_or(0);
        let mut index = vec![u32::MAX; max + 1];
        for (k, t) in tags.iter().enumerate() {
            index[*t] = k as u32;
            out.uv.push([coord[3 * k], coord[3 * k + 1]]);
        }
        let (mut etags, mut ne) = (std::ptr::null_mut(), 0usize);
        let (mut enodes, mut nn) = (std::ptr::null_mut(), 0usize);
        sys::gmshModelMeshGetElementsByType(
            2,
            &mut etags,
            &mut ne,
            &mut enodes,
            &mut nn,
            -1,
            0,
            1,
            &mut ierr,
        );
        check(ierr, "getElementsByType")?;
        let _ = take(etags, ne);
        let nodes = take(enodes, nn);
        for t in nodes.chunks(3) {
            out.triangles.push([index[t[0]], index[t[1]], index[t[2]]]);
        }
    }
    Ok(out)
}
