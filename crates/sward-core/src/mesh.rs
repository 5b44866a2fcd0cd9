//! Triangle meshes as ground for grass (SPEC §2, the paper's "general 3D scenes"): validation,
//! smooth vertex normals, and blade placement proportional to area and uniform inside each
//! triangle, with `up` from the face and interpolated vertex normals, on any orientation of
//! surface (walls, overhangs, a whole sphere).

use std::path::Path;

use glam::{Vec3, Vec4};

use crate::content::Contents;

/// What is wrong with a mesh given as ground.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    /// No triangles at all.
    #[error("the mesh has no triangles; grass needs at least one triangle of non-zero area")]
    NoTriangles,
    /// This vertex is not a finite point.
    #[error("mesh vertex {0} is not a finite point (NaN or infinity)")]
    NonFinite(usize),
    /// A triangle refers to a vertex that is not there.
    #[error("mesh triangle {triangle} refers to vertex {index}, but the mesh has only {vertices} vertices")]
    BadIndex {
        /// The triangle.
        triangle: usize,
        /// The vertex it refers to.
        index: u32,
        /// Vertices the mesh has.
        vertices: usize,
    },
    /// Every triangle is degenerate.
    #[error("every triangle of the mesh has zero area, so no grass can grow on it")]
    ZeroArea,
    /// A paint map (`[paint]`) could not be used.
    #[error(
        "cannot use paint map {path}: {reason} (a paint map is a PNG image, read as grey or colour, 2 to 2048 pixels a side)"
    )]
    Map {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// The file could not be read as a mesh.
    #[error("cannot load mesh {path}: {reason} (sward reads Wavefront OBJ (.obj) and glTF 2.0 (.gltf, .glb) meshes and PNG height maps)")]
    Load {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
}

/// An indexed triangle mesh with smooth (area-weighted) vertex normals.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<Vec3>,
    /// Triangles as three indices into `positions`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// A validated mesh; vertex normals are computed from the faces.
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<Mesh, MeshError> {
        if triangles.is_empty() {
            return Err(MeshError::NoTriangles);
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFinite(i));
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(MeshError::BadIndex {
                    triangle: t,
                    index,
                    vertices: positions.len(),
                });
            }
        }
        let mut mesh = Mesh {
            normals: vec![Vec3::ZERO; positions.len()],
            positions,
            triangles,
        };
        if mesh.area() <= 0.0 {
            return Err(MeshError::ZeroArea);
        }
        mesh.smooth_normals();
        Ok(mesh)
    }

    /// Corner positions of triangle `t`.
    pub(crate) fn corners(&self, t: usize) -> [Vec3; 3] {
        self.triangles[t].map(|i| self.positions[i as usize])
    }

    /// Twice-area-weighted face normal (its length is twice the triangle's area).
    pub(crate) fn face_cross(&self, t: usize) -> Vec3 {
        let [a, b, c] = self.corners(t);
        (b - a).cross(c - a)
    }

    fn smooth_normals(&mut self) {
        let mut sums = vec![Vec3::ZERO; self.positions.len()];
        for t in 0..self.triangles.len() {
            let n = self.face_cross(t);
            for i in self.triangles[t] {
                sums[i as usize] += n;
            }
        }
        self.normals = sums.into_iter().map(|n| n.normalize_or_zero()).collect();
    }

    /// The vertices as the ground's vertex stage pulls them (both renderers): position then
    /// normal, each a vec4 (w 1 and 0).
    pub fn pulled_vertices(&self) -> Vec<Vec4> {
        let pairs = self.positions.iter().zip(&self.normals);
        pairs.flat_map(|(p, n)| [p.extend(1.0), n.extend(0.0)]).collect()
    }

    /// Total area of the triangles.
    pub fn area(&self) -> f32 {
        (0..self.triangles.len())
            .map(|t| 0.5 * self.face_cross(t).length())
            .sum()
    }

    /// Every triangle of a Wavefront OBJ file (all its objects), scaled by `scale`.
    /// Load a mesh file, OBJ or glTF 2.0 by its extension, scaled about the origin.
    pub fn load(path: &std::path::Path, scale: f32) -> Result<Mesh, MeshError> {
        Mesh::load_from(&Contents::default(), path, scale)
    }

    /// The mesh at `path`, scaled about the origin: the one given under its name in
    /// `contents` (a mesh, or a file's bytes read by its extension), else the file on disk.
    pub fn load_from(contents: &Contents, path: &std::path::Path, scale: f32) -> Result<Mesh, MeshError> {
        if let Some(given) = contents.mesh(path) {
            let positions = given.positions.iter().map(|p| *p * scale).collect();
            return Mesh::new(positions, given.triangles.clone()).map_err(|e| MeshError::Load {
                path: path.display().to_string(),
                reason: e.to_string(),
            });
        }
        let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("obj") => Mesh::obj_from(contents, path, scale),
            Some("gltf" | "glb") => Mesh::gltf_from(contents, path, scale),
            _ => Err(MeshError::Load {
                path: path.display().to_string(),
                reason: "the file name ends in neither .obj, .gltf nor .glb".into(),
            }),
        }
    }

    /// Every triangle primitive of a glTF 2.0 file's default scene (or of all its nodes if it
    /// names none), placed by the node transforms. Images are not read: grass needs only shape.
    pub fn load_gltf(path: &std::path::Path, scale: f32) -> Result<Mesh, MeshError> {
        Mesh::gltf_from(&Contents::default(), path, scale)
    }

    /// [`Mesh::load_gltf`], its file and buffers read through `contents`.
    fn gltf_from(contents: &Contents, path: &std::path::Path, scale: f32) -> Result<Mesh, MeshError> {
        let fail = |reason: String| MeshError::Load {
            path: path.display().to_string(),
            reason,
        };
        let bytes = contents.read(path).map_err(fail)?;
        check_glb_length(&bytes).map_err(fail)?;
        let damaged = || fail("its accessors or buffers refer to what the file does not hold".into());
        let gltf = without_panics(|| gltf::Gltf::from_slice(&bytes))
            .ok_or_else(damaged)?
            .map_err(|e| fail(e.to_string()))?;
        let base = path.parent();
        let buffers = without_panics(|| gltf_buffers(&gltf.document, base, gltf.blob.clone(), contents))
            .ok_or_else(damaged)?
            .map_err(fail)?;
        let roots: Vec<gltf::Node> = match gltf.document.default_scene().or_else(|| gltf.document.scenes().next()) {
            Some(scene) => scene.nodes().collect(),
            None => gltf.document.nodes().collect(),
        };
        let mut mesh = Mesh {
            positions: Vec::new(),
            normals: Vec::new(),
            triangles: Vec::new(),
        };
        let root_transform = glam::Mat4::from_scale(Vec3::splat(scale));
        for node in roots {
            gather_gltf_node(&node, root_transform, &buffers, &mut mesh, 0).map_err(fail)?;
        }
        Mesh::new(mesh.positions, mesh.triangles).map_err(|e| fail(e.to_string()))
    }

    /// Load a Wavefront OBJ file, scaled about its origin by `scale`.
    pub fn load_obj(path: &std::path::Path, scale: f32) -> Result<Mesh, MeshError> {
        Mesh::obj_from(&Contents::default(), path, scale)
    }

    /// [`Mesh::load_obj`], its file read through `contents`.
    fn obj_from(contents: &Contents, path: &std::path::Path, scale: f32) -> Result<Mesh, MeshError> {
        let fail = |reason: String| MeshError::Load {
            path: path.display().to_string(),
            reason,
        };
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: true,
            ..Default::default()
        };
        let bytes = contents.read(path).map_err(fail)?;
        // Materials are not read: grass needs only the shape.
        let no_materials = |_: &std::path::Path| Err(tobj::LoadError::OpenFileFailed);
        let parsed = without_panics(|| tobj::load_obj_buf(&mut bytes.as_slice(), &options, no_materials))
            .ok_or_else(|| fail("a face refers to a vertex, texture coordinate or normal far out of range".into()))?;
        let (models, _materials) = parsed.map_err(|e| fail(e.to_string()))?;
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for model in models {
            let base = positions.len() as u32;
            positions.extend(
                model
                    .mesh
                    .positions
                    .as_chunks::<3>()
                    .0
                    .iter()
                    .map(|p| Vec3::new(p[0], p[1], p[2]) * scale),
            );
            triangles.extend(model.mesh.indices.as_chunks::<3>().0.iter().map(|t| {
                [
                    base.saturating_add(t[0]),
                    base.saturating_add(t[1]),
                    base.saturating_add(t[2]),
                ]
            }));
        }
        Mesh::new(positions, triangles).map_err(|e| fail(e.to_string()))
    }

    /// Rolling terrain: a `resolution`² grid over `size` (x, z) centred on the origin, heights from
    /// a few octaves of value noise up to `height`.
    pub fn terrain(size: glam::Vec2, height: f32, resolution: u32, seed: u64) -> Mesh {
        let n = resolution.clamp(2, 2048);
        let offset = glam::Vec2::splat((seed % 1024) as f32 * 17.3);
        let elevation = |x: f32, z: f32| {
            let q = glam::Vec2::new(x, z) / size.max_element().max(1e-3) * 4.0 + offset;
            let (mut sum, mut amplitude, mut frequency) = (0.0, 0.5, 1.0);
            for _ in 0..4 {
                sum += amplitude * crate::wind::value_noise(q * frequency);
                amplitude *= 0.5;
                frequency *= 2.0;
            }
            height * sum / 0.9375
        };
        let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
        for j in 0..=n {
            for i in 0..=n {
                let x = (i as f32 / n as f32 - 0.5) * size.x;
                let z = (j as f32 / n as f32 - 0.5) * size.y;
                positions.push(Vec3::new(x, elevation(x, z), z));
            }
        }
        let mut triangles = Vec::with_capacity((2 * n * n) as usize);
        for j in 0..n {
            for i in 0..n {
                let a = j * (n + 1) + i;
                triangles.push([a, a + n + 1, a + 1]);
                triangles.push([a + 1, a + n + 1, a + n + 2]);
            }
        }
        Mesh::new(positions, triangles).expect("a terrain grid is a valid mesh")
    }

    /// Terrain from a height map image (8- or 16-bit grey PNG; other formats are read as luma):
    /// black is y = 0, white is y = `height`, the image spans `size` (x, z) centred on the origin,
    /// one vertex per pixel (images larger than 1025 pixels a side are sampled down).
    pub fn heightmap(path: &std::path::Path, size: glam::Vec2, height: f32) -> Result<Mesh, MeshError> {
        Mesh::heightmap_from(&Contents::default(), path, size, height)
    }

    /// [`Mesh::heightmap`], its image the one given under its name in `contents` where given.
    pub fn heightmap_from(
        contents: &Contents,
        path: &std::path::Path,
        size: glam::Vec2,
        height: f32,
    ) -> Result<Mesh, MeshError> {
        let fail = |reason: String| MeshError::Load {
            path: path.display().to_string(),
            reason,
        };
        let image = contents.read_image(path).map_err(fail)?.into_luma16();
        let (w, h) = image.dimensions();
        if w < 2 || h < 2 {
            return Err(fail(format!(
                "a height map needs at least 2×2 pixels, this one has {w}×{h}"
            )));
        }
        let step = (w.max(h) - 1).div_ceil(1024).max(1);
        let (nx, nz) = ((w - 1) / step + 1, (h - 1) / step + 1);
        let mut positions = Vec::with_capacity((nx * nz) as usize);
        for j in 0..nz {
            for i in 0..nx {
                let value = image.get_pixel(i * step, j * step).0[0] as f32 / 65535.0;
                let x = (i as f32 / (nx - 1) as f32 - 0.5) * size.x;
                let z = (j as f32 / (nz - 1) as f32 - 0.5) * size.y;
                positions.push(Vec3::new(x, value * height, z));
            }
        }
        let mut triangles = Vec::with_capacity((2 * (nx - 1) * (nz - 1)) as usize);
        for j in 0..nz - 1 {
            for i in 0..nx - 1 {
                let a = j * nx + i;
                triangles.push([a, a + nx, a + 1]);
                triangles.push([a + 1, a + nx, a + nx + 1]);
            }
        }
        Mesh::new(positions, triangles).map_err(|e| fail(e.to_string()))
    }

    /// Extent of the mesh along x and z.
    /// The ground as a height field, if this mesh is a row-major grid of vertices over x and z (as
    /// `terrain` and `heightmap` build it); arbitrary meshes give `None`.
    pub fn height_grid(&self) -> Option<HeightGrid> {
        let first = *self.positions.first()?;
        let nx = self.positions.iter().take_while(|p| p.z == first.z).count();
        if nx < 2 || !self.positions.len().is_multiple_of(nx) {
            return None;
        }
        let nz = self.positions.len() / nx;
        let last = *self.positions.last()?;
        let grid = HeightGrid {
            nx: nx as u32,
            nz: nz as u32,
            min: glam::Vec2::new(first.x, first.z),
            max: glam::Vec2::new(last.x, last.z),
            heights: self.positions.iter().map(|p| p.y).collect(),
            span: self
                .positions
                .iter()
                .fold([f32::MAX, f32::MIN], |[lo, hi], p| [lo.min(p.y), hi.max(p.y)]),
        };
        // Every vertex where the grid says it is.
        let on_grid = self.positions.iter().enumerate().all(|(k, p)| {
            let at = grid.vertex_xz(k as u32 % grid.nx, k as u32 / grid.nx);
            (at - glam::Vec2::new(p.x, p.z)).abs().max_element() <= 1e-4 * (grid.max - grid.min).max_element()
        });
        (nz >= 2 && grid.max.cmpgt(grid.min).all() && on_grid).then_some(grid)
    }

    /// Extent of the mesh in x and z.
    pub fn footprint(&self) -> glam::Vec2 {
        let (lo, hi) = self
            .positions
            .iter()
            .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        glam::Vec2::new(hi.x - lo.x, hi.z - lo.z)
    }

    /// A UV sphere of `radius` around the origin, outward normals (a small planet).
    pub fn sphere(radius: f32, rings: u32, segments: u32) -> Mesh {
        let (rings, segments) = (rings.max(2), segments.max(3));
        let mut positions = Vec::new();
        for r in 0..=rings {
            let phi = std::f32::consts::PI * r as f32 / rings as f32;
            for s in 0..=segments {
                let theta = std::f32::consts::TAU * s as f32 / segments as f32;
                positions.push(radius * Vec3::new(phi.sin() * theta.cos(), phi.cos(), phi.sin() * theta.sin()));
            }
        }
        let row = segments + 1;
        let mut triangles = Vec::new();
        for r in 0..rings {
            for s in 0..segments {
                let (a, b) = (r * row + s, (r + 1) * row + s);
                // Counter-clockwise seen from outside, so face normals point outward.
                triangles.push([a, a + 1, b]);
                triangles.push([a + 1, b + 1, b]);
            }
        }
        let mut mesh = Mesh::new(positions, triangles).expect("a UV sphere is a valid mesh");
        // Seams and poles repeat vertices; the exact normal of a sphere is its position.
        mesh.normals = mesh.positions.iter().map(|p| p.normalize_or_zero()).collect();
        mesh
    }
}

/// A ground mesh that is a regular grid: heights of `nx` × `nz` vertices (row-major, x fastest)
/// spanning `min`..`max` in x and z, triangulated as `terrain` and `heightmap` do.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightGrid {
    /// Vertices along x.
    pub nx: u32,
    /// Vertices along z.
    pub nz: u32,
    /// Smallest x and z of the grid.
    pub min: glam::Vec2,
    /// Largest x and z of the grid.
    pub max: glam::Vec2,
    /// Height of each vertex, row-major, x fastest.
    pub heights: Vec<f32>,
    /// The lowest and highest of `heights`.
    pub span: [f32; 2],
}

impl HeightGrid {
    fn vertex_xz(&self, i: u32, j: u32) -> glam::Vec2 {
        let t = glam::Vec2::new(i as f32 / (self.nx - 1) as f32, j as f32 / (self.nz - 1) as f32);
        self.min + (self.max - self.min) * t
    }

    /// The height of the grid's triangles at (x, z), or `None` off the grid. Mirrored in
    /// `generate_grid.wesl`.
    pub fn height_at(&self, x: f32, z: f32) -> Option<f32> {
        let cells = glam::Vec2::new((self.nx - 1) as f32, (self.nz - 1) as f32);
        let q = (glam::Vec2::new(x, z) - self.min) / (self.max - self.min) * cells;
        if !(q.cmpge(glam::Vec2::ZERO).all() && q.cmple(cells).all()) {
            return None;
        }
        let cell = q.floor().min(cells - 1.0);
        let f = q - cell;
        let (i, j) = (cell.x as u32, cell.y as u32);
        let h = |di: u32, dj: u32| self.heights[((j + dj) * self.nx + i + di) as usize];
        // The diagonal runs from (i + 1, j) to (i, j + 1).
        Some(if f.x + f.y <= 1.0 {
            h(0, 0) + f.x * (h(1, 0) - h(0, 0)) + f.y * (h(0, 1) - h(0, 0))
        } else {
            h(1, 1) + (1.0 - f.x) * (h(0, 1) - h(1, 1)) + (1.0 - f.y) * (h(1, 0) - h(1, 1))
        })
    }
}

/// A binary glTF's header states the file's length; the reader allocates what it states before
/// reading, so a damaged header (a length below the header's own, or beyond the file) would ask
/// for up to 4 GiB. Text glTF passes.
fn check_glb_length(bytes: &[u8]) -> Result<(), String> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let stated = bytes.get(8..12).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    match stated {
        Some(n) if n as usize == bytes.len() => Ok(()),
        Some(n) => Err(format!(
            "its binary header says it is {n} bytes long, but it has {}",
            bytes.len()
        )),
        None => Err("its binary header is cut short".into()),
    }
}

thread_local! {
    /// Whether this thread is inside [`without_panics`].
    static QUIET: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// The bytes of every buffer a glTF document names, as its `uri`s and a .glb's binary chunk
/// hold them (a `data:` URI's base64, a file beside `base`), each padded to four bytes; or why
/// not, in words.
fn gltf_buffers(
    document: &gltf::Document,
    base: Option<&Path>,
    mut blob: Option<Vec<u8>>,
    contents: &Contents,
) -> Result<Vec<Vec<u8>>, String> {
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let mut data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or("it names a binary chunk it does not have")?,
            gltf::buffer::Source::Uri(uri) => read_gltf_uri(uri, base, contents)?,
        };
        if data.len() < buffer.length() {
            return Err(format!(
                "its buffer {} holds {} bytes, and it says {}",
                buffer.index(),
                data.len(),
                buffer.length()
            ));
        }
        data.resize(data.len().next_multiple_of(4), 0);
        buffers.push(data);
    }
    Ok(buffers)
}

/// The bytes at a glTF buffer's `uri`: inline base64 (`data:…;base64,…`), a `file:` path, or a
/// path relative to `base` (percent-encoded).
fn read_gltf_uri(uri: &str, base: Option<&Path>, contents: &Contents) -> Result<Vec<u8>, String> {
    if let Some(data) = uri.strip_prefix("data:") {
        let encoded = data.split_once(";base64,").map_or(data, |(_, encoded)| encoded);
        return decode_base64(encoded).ok_or_else(|| "a buffer's data URI is not base64".to_string());
    }
    let path = gltf_uri_path(uri, base)?;
    contents
        .read(&path)
        .map_err(|e| format!("its buffer {} could not be read: {e}", path.display()))
}

/// The file a glTF buffer's (not inline) `uri` names: a `file:` path, or a path relative to
/// `base` (percent-encoded).
fn gltf_uri_path(uri: &str, base: Option<&Path>) -> Result<std::path::PathBuf, String> {
    match uri.strip_prefix("file://").or_else(|| uri.strip_prefix("file:")) {
        Some(path) => Ok(std::path::PathBuf::from(path)),
        None if uri.contains(':') => Err(format!("it names a buffer at {uri}, which is not a file")),
        None => Ok(base.unwrap_or(Path::new("")).join(percent_decoded(uri))),
    }
}

/// The files beside it that the glTF file at `path` holding `bytes` reads its buffers from (none
/// for a `.glb` or inline buffers), as [`Mesh::load_from`] names them in its contents: what an
/// asset server reads with the file.
pub fn gltf_buffer_files(path: &Path, bytes: &[u8]) -> Vec<std::path::PathBuf> {
    let Some(Ok(gltf)) = without_panics(|| gltf::Gltf::from_slice(bytes)) else {
        return Vec::new();
    };
    let uris: Vec<String> = gltf
        .document
        .buffers()
        .filter_map(|b| match b.source() {
            gltf::buffer::Source::Uri(uri) if !uri.starts_with("data:") => Some(uri.to_string()),
            _ => None,
        })
        .collect();
    uris.iter()
        .filter_map(|uri| gltf_uri_path(uri, path.parent()).ok())
        .collect()
}

/// Standard base64 (padding optional), or None where a character is not of it.
fn decode_base64(text: &str) -> Option<Vec<u8>> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let digits = text.trim_end_matches('=').as_bytes();
    let mut out = Vec::with_capacity(digits.len() * 3 / 4);
    let (mut bits, mut held) = (0u32, 0u32);
    for &c in digits {
        bits = bits << 6 | value(c)? as u32;
        held += 6;
        if held >= 8 {
            held -= 8;
            out.push((bits >> held) as u8);
        }
    }
    Some(out)
}

/// `%XX` escapes turned into their bytes (a malformed one kept as written).
fn percent_decoded(text: &str) -> String {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes.get(i + 1..i + 3).and_then(|h| std::str::from_utf8(h).ok());
        match (bytes[i], hex.and_then(|h| u8::from_str_radix(h, 16).ok())) {
            (b'%', Some(byte)) => {
                out.push(byte);
                i += 3;
            }
            (byte, _) => {
                out.push(byte);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// `read`'s result, or `None` where it panicked. The OBJ and glTF readers panic on some damaged
/// files (indices they do not check, arithmetic that overflows where it is checked); that is a
/// damaged file, which the caller says in one sentence like any other — so the panic is neither
/// let through nor printed. Other threads' panics are reported as before.
fn without_panics<T>(read: impl FnOnce() -> T) -> Option<T> {
    static QUIET_HOOK: std::sync::Once = std::sync::Once::new();
    QUIET_HOOK.call_once(|| {
        let report = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(|q| q.get()) {
                report(info);
            }
        }));
    });
    QUIET.with(|q| q.set(true));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(read)).ok();
    QUIET.with(|q| q.set(false));
    result
}

/// How deep glTF nodes may nest: a file whose node lists itself as its own descendant would
/// otherwise be walked until the stack runs out.
const MAX_NODE_DEPTH: usize = 64;

/// Whether `primitive`'s positions are three floats and its indices (if any) whole numbers, as
/// the glTF specification requires; a file that says otherwise is read by nobody.
fn readable(primitive: &gltf::Primitive) -> bool {
    use gltf::accessor::{DataType, Dimensions};
    let positions = primitive
        .get(&gltf::Semantic::Positions)
        .is_some_and(|a| a.data_type() == DataType::F32 && a.dimensions() == Dimensions::Vec3);
    let indices = primitive.indices().is_none_or(|a| {
        a.dimensions() == Dimensions::Scalar && matches!(a.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
    });
    positions && indices
}

/// Append the triangles of `node` and its children, transformed by `parent` and their own
/// transforms, to `out` (positions and triangles only; `Mesh::new` computes normals). Fails
/// where the nodes nest deeper than `MAX_NODE_DEPTH` or a primitive is not readable.
fn gather_gltf_node(
    node: &gltf::Node,
    parent: glam::Mat4,
    buffers: &[Vec<u8>],
    out: &mut Mesh,
    depth: usize,
) -> Result<(), String> {
    if depth > MAX_NODE_DEPTH {
        return Err(format!(
            "its nodes nest more than {MAX_NODE_DEPTH} deep (a node inside itself?)"
        ));
    }
    let transform = parent * glam::Mat4::from_cols_array_2d(&node.transform().matrix());
    if let Some(mesh) = node.mesh() {
        for primitive in mesh.primitives() {
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                continue;
            }
            if !readable(&primitive) {
                return Err(format!(
                    "mesh {} has a primitive whose positions are not three floats or whose indices are not whole numbers",
                    mesh.index()
                ));
            }
            let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| d.as_slice()));
            let Some(positions) = reader.read_positions() else {
                continue;
            };
            let base = out.positions.len() as u32;
            out.positions
                .extend(positions.map(|p| transform.transform_point3(Vec3::from_array(p))));
            let count = out.positions.len() as u32 - base;
            let indices: Vec<u32> = match reader.read_indices() {
                Some(indices) => indices.into_u32().collect(),
                None => (0..count).collect(),
            };
            out.triangles.extend(indices.as_chunks::<3>().0.iter().map(|t| {
                [
                    base.saturating_add(t[0]),
                    base.saturating_add(t[1]),
                    base.saturating_add(t[2]),
                ]
            }));
        }
    }
    for child in node.children() {
        gather_gltf_node(&child, transform, buffers, out, depth + 1)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gltf_buffer_s_base64_and_percent_encoded_path_are_read_as_written() {
        assert_eq!(decode_base64("c3dhcmQ=").unwrap(), b"sward");
        assert_eq!(decode_base64("c3dhcmQ").unwrap(), b"sward", "padding is optional");
        assert_eq!(decode_base64("AAECAw==").unwrap(), [0, 1, 2, 3]);
        assert!(decode_base64("c3d!cmQ=").is_none());
        assert_eq!(percent_decoded("my%20mesh.bin"), "my mesh.bin");
        assert_eq!(percent_decoded("100%.bin"), "100%.bin", "a malformed escape is kept");
        let read = |uri: &str| read_gltf_uri(uri, None, &Contents::default());
        assert_eq!(
            read("data:application/octet-stream;base64,AAECAw==").unwrap(),
            [0, 1, 2, 3]
        );
        assert!(read("https://example.org/mesh.bin").unwrap_err().contains("not a file"));
    }
    use crate::field::{grow_on_mesh, FieldDesc};

    fn desc(blades: u32) -> FieldDesc {
        FieldDesc {
            blades,
            ..FieldDesc::default()
        }
    }

    #[test]
    fn blades_on_a_sphere_stand_on_it_and_point_outward() {
        let planet = Mesh::sphere(5.0, 24, 48);
        let blades = grow_on_mesh(&planet, &desc(5000));
        assert_eq!(blades.len(), 5000);
        for b in &blades {
            let r = b.root().length();
            // Roots lie on the faceted surface, slightly inside the true sphere.
            assert!((4.9..=5.0001).contains(&r), "root at radius {r}");
            assert!(b.up().dot(b.root().normalize()) > 0.99, "up {} at {}", b.up(), b.root());
            assert!(b.width_dir().dot(b.up()).abs() < 1e-4);
        }
    }

    #[test]
    fn density_follows_area_not_triangle_count() {
        // Two squares of equal area, one cut into 2 triangles and one into 32: equal blade counts.
        let mut positions = vec![];
        let mut triangles = vec![];
        let quad = |positions: &mut Vec<Vec3>, triangles: &mut Vec<[u32; 3]>, x0: f32, n: u32| {
            let base = positions.len() as u32;
            for j in 0..=n {
                for i in 0..=n {
                    positions.push(Vec3::new(x0 + i as f32 / n as f32, 0.0, j as f32 / n as f32));
                }
            }
            for j in 0..n {
                for i in 0..n {
                    let a = base + j * (n + 1) + i;
                    triangles.push([a, a + n + 1, a + 1]);
                    triangles.push([a + 1, a + n + 1, a + n + 2]);
                }
            }
        };
        quad(&mut positions, &mut triangles, 0.0, 1);
        quad(&mut positions, &mut triangles, 2.0, 4);
        let mesh = Mesh::new(positions, triangles).unwrap();
        let blades = grow_on_mesh(&mesh, &desc(20_000));
        let left = blades.iter().filter(|b| b.root().x < 1.5).count();
        assert!((9_600..=10_400).contains(&left), "{left} of 20000 on the coarse square");
        // Uniform inside a triangle: the coarse square's two halves get equal shares too.
        let corner = blades.iter().filter(|b| b.root().x < 0.5 && b.root().z < 0.5).count();
        assert!(
            (2_300..=2_700).contains(&corner),
            "{corner} in a quarter of the coarse square"
        );
        assert!(
            blades.iter().all(|b| (b.up() - Vec3::Y).length() < 1e-5),
            "a flat mesh points up"
        );
    }

    #[test]
    fn bad_meshes_are_named() {
        assert_eq!(Mesh::new(vec![Vec3::ZERO; 3], vec![]), Err(MeshError::NoTriangles));
        let nan = vec![Vec3::ZERO, Vec3::X, Vec3::new(f32::NAN, 0.0, 0.0)];
        assert_eq!(Mesh::new(nan, vec![[0, 1, 2]]), Err(MeshError::NonFinite(2)));
        let e = Mesh::new(vec![Vec3::ZERO; 3], vec![[0, 1, 7]]).unwrap_err();
        assert!(e.to_string().contains("vertex 7") && e.to_string().contains("only 3"));
        assert_eq!(
            Mesh::new(vec![Vec3::ZERO; 3], vec![[0, 1, 2]]),
            Err(MeshError::ZeroArea)
        );
    }

    #[test]
    fn terrain_blades_stand_on_the_terrain_and_obj_files_load() {
        let hills = Mesh::terrain(glam::Vec2::splat(20.0), 3.0, 64, 5);
        assert!(hills.positions.iter().any(|p| p.y > 1.0), "the terrain has hills");
        let blades = grow_on_mesh(&hills, &desc(2000));
        assert!(blades
            .iter()
            .all(|b| b.up().y > 0.3 && b.root().y >= -1e-3 && b.root().y <= 3.0));
        let dir = std::env::temp_dir().join(format!("sward-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let obj = dir.join("wall.obj");
        // A vertical wall facing +z: blades grow sideways out of it.
        std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
        let wall = Mesh::load_obj(&obj, 2.0).unwrap();
        assert_eq!(wall.triangles.len(), 2);
        assert!((wall.area() - 4.0).abs() < 1e-5);
        assert!(grow_on_mesh(&wall, &desc(100))
            .iter()
            .all(|b| (b.up() - Vec3::Z).length() < 1e-5));
        // A 16-bit ramp height map: heights rise linearly along x.
        let ramp = image::ImageBuffer::from_fn(9, 5, |x, _| image::Luma([(x * 65535 / 8) as u16]));
        let png = dir.join("ramp.png");
        ramp.save(&png).unwrap();
        let slope = Mesh::heightmap(&png, glam::Vec2::new(8.0, 4.0), 2.0).unwrap();
        assert_eq!(slope.positions.len(), 45);
        let top = slope.positions.iter().map(|p| p.y).fold(0.0, f32::max);
        assert!((top - 2.0).abs() < 1e-4, "white is the full height, got {top}");
        assert!(
            grow_on_mesh(&slope, &desc(50)).iter().all(|b| b.up().x < -0.1),
            "blades lean off the slope"
        );
        let e = Mesh::heightmap(&dir.join("none.png"), glam::Vec2::ONE, 1.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("none.png"), "{e}");
        let e = Mesh::load_obj(&dir.join("missing.obj"), 1.0).unwrap_err().to_string();
        assert!(e.contains("missing.obj") && e.contains("OBJ"), "{e}");
        let e = Mesh::load(&dir.join("rock.stl"), 1.0).unwrap_err().to_string();
        assert!(e.contains("rock.stl") && e.contains(".glb"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A glTF file with one quad (two indexed triangles) in an embedded base64 buffer, under a
    /// node that turns it upright and lifts it by 3.
    fn write_quad_gltf(path: &std::path::Path) {
        let positions: [[f32; 3]; 4] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 1.0], [0.0, 0.0, 1.0]];
        let indices: [u16; 6] = [0, 2, 1, 0, 3, 2];
        let mut bytes: Vec<u8> = bytemuck::cast_slice(&positions).to_vec();
        bytes.extend_from_slice(bytemuck::cast_slice(&indices));
        let data = base64_encode(&bytes);
        // Rotation of 90° about x: the quad's +y normal becomes +z.
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
"nodes":[{{"mesh":0,"translation":[0,3,0],"rotation":[{r},0,0,{h}]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],
"buffers":[{{"byteLength":{len},"uri":"data:application/octet-stream;base64,{data}"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":12}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,0,1]}},
{{"bufferView":1,"componentType":5123,"count":6,"type":"SCALAR"}}]}}"#,
            r = h,
            len = bytes.len(),
        );
        std::fs::write(path, json).unwrap();
    }

    fn base64_encode(bytes: &[u8]) -> String {
        const TABLE: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut out = String::new();
        for chunk in bytes.chunks(3) {
            let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
            let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
            for k in 0..4 {
                if k <= chunk.len() {
                    out.push(TABLE[(n >> (18 - 6 * k) & 63) as usize] as char);
                } else {
                    out.push('=');
                }
            }
        }
        out
    }

    #[test]
    fn gltf_meshes_load_with_their_node_transforms() {
        let dir = std::env::temp_dir().join(format!("sward-gltf-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("quad.gltf");
        write_quad_gltf(&path);
        let quad = Mesh::load(&path, 2.0).unwrap();
        assert_eq!(quad.triangles.len(), 2);
        assert!((quad.area() - 4.0).abs() < 1e-4, "area {}", quad.area());
        // Scaled by 2 after the node's lift of 3 and its turn upright.
        assert!(quad
            .positions
            .iter()
            .all(|p| (p.y - 6.0).abs() < 1e-4 || (p.y - 4.0).abs() < 1e-4));
        assert!(quad.positions.iter().all(|p| p.z.abs() < 1e-4));
        assert!(grow_on_mesh(&quad, &desc(50))
            .iter()
            .all(|b| (b.up() - Vec3::Z).length() < 1e-4));
        std::fs::write(dir.join("broken.glb"), b"not a glb").unwrap();
        let e = Mesh::load(&dir.join("broken.glb"), 1.0).unwrap_err().to_string();
        assert!(e.contains("broken.glb"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn same_seed_same_blades_on_a_mesh() {
        let planet = Mesh::sphere(2.0, 8, 16);
        assert_eq!(grow_on_mesh(&planet, &desc(300)), grow_on_mesh(&planet, &desc(300)));
    }
}
