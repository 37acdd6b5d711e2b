//! Meshes from glTF files (`.glb`, or `.gltf` with its buffers beside it)
//! for the CPU reference and the command line: every triangle primitive of
//! the default scene, with its node's transform and its material: base
//! colour, metallic and roughness, emission (`KHR_materials_emissive_strength`
//! too), their textures (PNG), the normal map and the alpha mask (an
//! alpha-blended material is drawn opaque, with a warning). A primitive that cannot be traced
//! (no triangles, NaN positions) is skipped with a warning; a file with
//! nothing traceable is an error. Bevy apps load glTF through Bevy's own
//! loader instead (see `crate::meshes`).
//!
//! ```
//! let loaded = bevy_manifold_core::mesh::gltf::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/models/suzanne.glb")).unwrap();
//! assert_eq!(loaded.parts.len(), 1);
//! assert_eq!(loaded.parts[0].mesh.triangles.len(), 3936);
//! ```

use super::{MeshError, MeshMaterial, Texture, TriMesh};
use glam::Mat4;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Most node instances walked in one file's scene (a graph that reuses
/// children can name exponentially many).
pub const MAX_NODE_VISITS: usize = 100_000;

/// Most texels a side of a glTF texture may have.
pub const MAX_TEXTURE_SIDE: u32 = 4096;

/// Why a glTF file gave nothing to trace.
#[derive(Debug, thiserror::Error)]
pub enum GltfError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// Not glTF, or broken glTF.
    #[error("{path}: not a readable glTF file: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The parser's message.
        message: String,
    },
    /// Nothing in it can be traced.
    #[error("{path}: no traceable triangles ({})", .warnings.join("; "))]
    NothingToTrace {
        /// The file.
        path: PathBuf,
        /// What was wrong with each primitive.
        warnings: Vec<String>,
    },
}

/// One triangle primitive of a glTF scene.
#[derive(Clone, Debug)]
pub struct MeshPart {
    /// `mesh name / primitive index`.
    pub name: String,
    /// Its triangles, in the primitive's own coordinates.
    pub mesh: TriMesh,
    /// Where its node puts it in the file's scene.
    pub transform: Mat4,
    /// Its surface.
    pub material: MeshMaterial,
}

/// What a glTF file gave: its traceable parts, and a warning for each
/// primitive that was skipped.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The parts.
    pub parts: Vec<MeshPart>,
    /// One line per skipped primitive or texture.
    pub warnings: Vec<String>,
}

/// Reads a glTF file.
///
/// # Errors
/// [`GltfError`]: unreadable, unparsable, or nothing traceable in it.
pub fn load(path: impl AsRef<Path>) -> Result<Loaded, GltfError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| GltfError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    from_slice(&bytes, path)
}

/// Reads glTF from memory; `path` names it in messages and locates
/// external buffers and images.
///
/// # Errors
/// As [`load`].
pub fn from_slice(bytes: &[u8], path: &Path) -> Result<Loaded, GltfError> {
    // The glTF crate's validation indexes lists a broken file may lack
    // (found by fuzzing: a POSITION attribute with no "accessors" at all
    // panicked inside gltf-json; `read` now checks that case first). Any
    // other such panic is this file's error, not the program's end.
    std::panic::catch_unwind(|| read(bytes, path)).unwrap_or_else(|_| {
        Err(GltfError::Parse {
            path: path.to_path_buf(),
            message: "the glTF reader failed on a field it does not check (an index past its list?)".into(),
        })
    })
}

fn read(bytes: &[u8], path: &Path) -> Result<Loaded, GltfError> {
    let parse = |message: String| GltfError::Parse {
        path: path.to_path_buf(),
        message,
    };
    // Parsed first, then every accessor index a primitive names checked
    // against the accessor list, then validated: the crate's validation
    // indexes that list without a bound check.
    let raw = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| parse(e.to_string()))?;
    let root = raw.document.into_json();
    let accessors = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let named = prim.attributes.values().chain(prim.indices.as_ref());
            if let Some(bad) = named.map(|i| i.value()).find(|&i| i >= accessors) {
                return Err(parse(format!(
                    "meshes[{m}].primitives[{p}] names accessor {bad}, but the file has {accessors}"
                )));
            }
        }
    }
    let document = gltf::Document::from_json(root).map_err(|e| parse(e.to_string()))?;
    let gltf = gltf::Gltf {
        document,
        blob: raw.blob,
    };
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut buffers = Vec::new();
    for b in gltf.buffers() {
        let data = match b.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or_else(|| parse("the GLB has no binary chunk".into()))?,
            gltf::buffer::Source::Uri(uri) => {
                if uri.starts_with("data:") {
                    data_uri(uri).map_err(|e| parse(format!("buffers[{}]: {e}", b.index())))?
                } else {
                    std::fs::read(dir.join(uri)).map_err(|e| parse(format!("buffer '{uri}': {e}")))?
                }
            }
        };
        buffers.push(data);
    }
    let mut loaded = Loaded {
        parts: Vec::new(),
        warnings: Vec::new(),
    };
    let mut textures: Vec<Option<Option<Arc<Texture>>>> = vec![None; gltf.textures().len()];
    let Some(scene) = gltf.default_scene().or_else(|| gltf.scenes().next()) else {
        return Err(parse("no scene".into()));
    };
    // Depth first, each entry with the chain of nodes above it: a node that
    // is its own ancestor (a cycle, which glTF forbids and a broken file
    // can still hold) is reported and its subtree left out, and a graph
    // that reuses children is walked at most MAX_NODE_VISITS times.
    let mut stack: Vec<(gltf::Node, Mat4, Vec<usize>)> =
        scene.nodes().map(|n| (n, Mat4::IDENTITY, Vec::new())).collect();
    let mut visits = 0usize;
    let mut triangles = 0usize;
    while let Some((node, parent, above)) = stack.pop() {
        visits += 1;
        if visits > MAX_NODE_VISITS {
            loaded.warnings.push(format!(
                "{}: the node graph has more than {MAX_NODE_VISITS} node instances; the rest is left out",
                path.display()
            ));
            break;
        }
        let transform = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        let mut chain = above;
        chain.push(node.index());
        for child in node.children() {
            if chain.contains(&child.index()) {
                loaded.warnings.push(format!(
                    "{}: node {} lists node {} below itself (a cycle); that branch is left out",
                    path.display(),
                    node.index(),
                    child.index()
                ));
                continue;
            }
            stack.push((child, transform, chain.clone()));
        }
        let Some(mesh) = node.mesh() else { continue };
        for prim in mesh.primitives() {
            let name = format!("{}/{}", mesh.name().unwrap_or("mesh"), prim.index());
            match part(&prim, &buffers, dir, &mut textures, &mut loaded.warnings) {
                Ok(mesh) if triangles + mesh.0.triangles.len() > super::MAX_TRIANGLES => {
                    loaded.warnings.push(format!(
                        "{}: {name}: the file's meshes would pass {} triangles in all; left out",
                        path.display(),
                        super::MAX_TRIANGLES
                    ));
                }
                Ok(mesh) => {
                    triangles += mesh.0.triangles.len();
                    loaded.parts.push(MeshPart {
                        name,
                        mesh: mesh.0,
                        transform,
                        material: mesh.1,
                    });
                }
                Err(e) => loaded.warnings.push(format!("{}: {name}: {e}", path.display())),
            }
        }
    }
    if loaded.parts.is_empty() {
        return Err(GltfError::NothingToTrace {
            path: path.to_path_buf(),
            warnings: loaded.warnings,
        });
    }
    Ok(loaded)
}

fn part(
    prim: &gltf::Primitive,
    buffers: &[Vec<u8>],
    dir: &Path,
    textures: &mut [Option<Option<Arc<Texture>>>],
    warnings: &mut Vec<String>,
) -> Result<(TriMesh, MeshMaterial), String> {
    if prim.mode() != gltf::mesh::Mode::Triangles {
        return Err(format!("{:?} primitives are not traced", prim.mode()));
    }
    // Accessor counts are the file's word, not its size (a sparse accessor
    // of a few bytes can claim billions): checked before anything is read.
    for (semantic, accessor) in prim.attributes() {
        if accessor.count() > super::MAX_VERTICES {
            return Err(format!(
                "{semantic:?} has {} entries, more than the {} a traced mesh may have",
                accessor.count(),
                super::MAX_VERTICES
            ));
        }
    }
    if let Some(indices) = prim.indices().filter(|i| i.count() > 3 * super::MAX_TRIANGLES) {
        return Err(format!(
            "{} indices, more than the {} triangles a traced mesh may have",
            indices.count(),
            super::MAX_TRIANGLES
        ));
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let positions: Vec<[f32; 3]> = reader.read_positions().ok_or("no POSITION attribute")?.collect();
    let normals = reader.read_normals().map(Iterator::collect);
    let uvs = reader.read_tex_coords(0).map(|t| t.into_f32().collect());
    let indices: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let triangles = indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let mesh = TriMesh::new(positions, normals, uvs, triangles).map_err(|e: MeshError| e.to_string())?;
    let material = prim.material();
    let pbr = material.pbr_metallic_roughness();
    let [r, g, b, a] = pbr.base_color_factor();
    let mut load = |t: gltf::Texture, what: &str| {
        textures[t.index()]
            .get_or_insert_with(|| match texture(&t, buffers, dir) {
                Ok(t) => Some(Arc::new(t)),
                Err(e) => {
                    warnings.push(format!("texture {}: {e}; the {what} is drawn without it", t.index()));
                    None
                }
            })
            .clone()
    };
    let texture = pbr.base_color_texture().and_then(|i| load(i.texture(), "base colour"));
    let metallic_roughness = pbr
        .metallic_roughness_texture()
        .and_then(|i| load(i.texture(), "metallic and roughness"));
    let emissive_texture = material.emissive_texture().and_then(|i| load(i.texture(), "emission"));
    let normal_map = material.normal_texture().and_then(|i| load(i.texture(), "normal"));
    let strength = material.emissive_strength().unwrap_or(1.0);
    let alpha_cutoff = match material.alpha_mode() {
        gltf::material::AlphaMode::Mask => Some(material.alpha_cutoff().unwrap_or(0.5)),
        gltf::material::AlphaMode::Opaque => None,
        gltf::material::AlphaMode::Blend => {
            warnings.push(format!(
                "material {}: alpha blending is drawn opaque",
                material.index().map_or("default".into(), |i| i.to_string())
            ));
            None
        }
    };
    let out = MeshMaterial {
        base_color: [r, g, b],
        texture,
        alpha: a,
        alpha_cutoff,
        // A primitive without a material keeps the classic look (glTF's
        // default material would be a rough metal).
        pbr: material.index().map(|_| crate::material::Pbr {
            metallic: pbr.metallic_factor(),
            roughness: pbr.roughness_factor(),
        }),
        metallic_roughness,
        emissive: material.emissive_factor().map(|c| c * strength),
        emissive_texture,
        normal_map,
    };
    out.check().map_err(|e| format!("material: {e}"))?;
    Ok((mesh, out))
}

/// The bytes of a base64 data URI, `data:[<media type>];base64,<data>`,
/// as Blender's "glTF Embedded" export and many sample models embed their
/// buffers and images. They are no larger than the file they are in
/// (three bytes for four characters), and images go through the same
/// decoder and caps as image files.
fn data_uri(uri: &str) -> Result<Vec<u8>, String> {
    use base64::Engine as _;
    let Some((head, data)) = uri.split_once(',') else {
        return Err("a data URI without a comma before its data".into());
    };
    if !head.ends_with(";base64") {
        return Err(format!(
            "a data URI that is not base64 ('{}'): glTF embeds base64 only",
            head.chars().take(60).collect::<String>()
        ));
    }
    base64::engine::general_purpose::STANDARD
        .decode(data.trim_end())
        .map_err(|e| format!("a data URI whose base64 is broken ({e})"))
}

fn texture(t: &gltf::Texture, buffers: &[Vec<u8>], dir: &Path) -> Result<Texture, String> {
    let bytes = match t.source().source() {
        gltf::image::Source::View { view, .. } => {
            let b = buffers.get(view.buffer().index()).ok_or("missing buffer")?;
            b.get(view.offset()..view.offset() + view.length())
                .ok_or("image view out of its buffer")?
                .to_vec()
        }
        gltf::image::Source::Uri { uri, .. } => {
            if uri.starts_with("data:") {
                data_uri(uri)?
            } else {
                std::fs::read(dir.join(uri)).map_err(|e| format!("'{uri}': {e}"))?
            }
        }
    };
    // The decoder refuses sizes past the cap before it allocates them.
    let mut reader = image::ImageReader::new(std::io::Cursor::new(&bytes))
        .with_guessed_format()
        .map_err(|e| format!("cannot read it ({e})"))?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    limits.max_alloc = Some(4 * super::MAX_TEXELS);
    reader.limits(limits);
    let img = reader
        .decode()
        .map_err(|e| format!("cannot decode it ({e}); only PNG is built in, at most {MAX_TEXTURE_SIDE} texels a side"))?
        .to_rgba8();
    Texture::new(
        img.width(),
        img.height(),
        img.pixels().map(|p| u32::from_le_bytes(p.0)).collect(),
    )
}
