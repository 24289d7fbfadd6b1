//! The JavaScript API (wasm-bindgen), identical in the browser and in node.
//!
//! Every fallible call returns `Result<_, JsError>`, which wasm-bindgen turns into a thrown
//! JavaScript `Error` whose message names the problem; nothing here panics on user input.
//! Typed arrays are copies: JavaScript may keep them after the `Character` is freed.

use wasm_bindgen::prelude::*;

use crate::character::Character as CoreCharacter;
use crate::import;

/// Installs the panic hook that prints Rust panics to the console (called once on load).
#[wasm_bindgen(start)]
pub fn start() {
    console_error_panic_hook::set_once();
}

/// A skinned glTF character loaded into the core.
#[wasm_bindgen]
pub struct Character {
    inner: CoreCharacter,
}

#[wasm_bindgen]
impl Character {
    /// Loads a binary glTF (`.glb`).
    ///
    /// Throws an `Error` naming the problem when the bytes are not a usable skinned glTF.
    #[wasm_bindgen(js_name = fromGlb)]
    pub fn from_glb(bytes: &[u8]) -> Result<Character, JsError> {
        let inner = import::from_glb(bytes).map_err(|e| JsError::new(&e.to_string()))?;
        Ok(Character { inner })
    }

    /// Loads a JSON glTF (`.gltf`); `resolve(uri)` returns the bytes of an external buffer or
    /// image as a `Uint8Array`, or `null`/`undefined` when it has none. `data:` URIs need no
    /// resolver.
    ///
    /// Throws an `Error` naming the problem (including a URI the resolver could not supply).
    #[wasm_bindgen(js_name = fromGltf)]
    pub fn from_gltf(json: &[u8], resolve: &js_sys::Function) -> Result<Character, JsError> {
        let mut resolver = |uri: &str| -> Option<Vec<u8>> {
            let value = resolve.call1(&JsValue::NULL, &JsValue::from_str(uri)).ok()?;
            if value.is_null() || value.is_undefined() {
                return None;
            }
            Some(js_sys::Uint8Array::new(&value).to_vec())
        };
        let inner = import::from_gltf(json, &mut resolver).map_err(|e| JsError::new(&e.to_string()))?;
        Ok(Character { inner })
    }

    /// Number of triangles of the merged mesh.
    #[wasm_bindgen(getter, js_name = triangleCount)]
    pub fn triangle_count(&self) -> usize {
        self.inner.mesh.triangle_count()
    }

    /// Number of vertices of the merged mesh (after welding files without an index buffer).
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.inner.mesh.vertex_count()
    }

    /// Number of skin joints (including the nodes that carry rigid parts).
    #[wasm_bindgen(getter, js_name = jointCount)]
    pub fn joint_count(&self) -> usize {
        self.inner.skeleton.joints.len()
    }

    /// Number of mesh primitives merged into the mesh.
    #[wasm_bindgen(getter, js_name = primitiveCount)]
    pub fn primitive_count(&self) -> usize {
        self.inner.mesh.primitives.len()
    }

    /// Names of the animation clips, in file order.
    #[wasm_bindgen(getter, js_name = clipNames)]
    pub fn clip_names(&self) -> Vec<String> {
        self.inner.clips.iter().map(|c| c.name.clone()).collect()
    }

    /// What the importer dropped or changed (morph targets, skipped primitives, …).
    #[wasm_bindgen(getter)]
    pub fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    /// Duration of clip `name` in seconds.
    ///
    /// Throws when there is no clip of that name.
    #[wasm_bindgen(js_name = clipDuration)]
    pub fn clip_duration(&self, name: &str) -> Result<f64, JsError> {
        Ok(self.find_clip(name)?.duration() as f64)
    }

    /// The triangle list, three vertex indices per triangle.
    pub fn indices(&self) -> Vec<u32> {
        self.inner.mesh.indices.clone()
    }

    /// Bind-space positions, xyz per vertex.
    #[wasm_bindgen(js_name = bindPositions)]
    pub fn bind_positions(&self) -> Vec<f32> {
        flatten(&self.inner.mesh.positions)
    }

    /// CPU-skinned positions (xyz per vertex, whole mesh) of clip `clipName` at `timeSeconds`
    /// (looping).
    ///
    /// Throws when there is no clip of that name or the time is not a finite number.
    #[wasm_bindgen(js_name = skinnedPositions)]
    pub fn skinned_positions(&self, clip_name: &str, time_seconds: f64) -> Result<Vec<f32>, JsError> {
        if !time_seconds.is_finite() {
            return Err(JsError::new(&format!("time must be a finite number of seconds, got {time_seconds}")));
        }
        let clip = self.find_clip(clip_name)?;
        let pose = self.inner.pose_at(clip, time_seconds as f32);
        Ok(flatten(&self.inner.skinned_positions(&pose)))
    }
}

impl Character {
    fn find_clip(&self, name: &str) -> Result<&crate::animation::Clip, JsError> {
        self.inner.clip(name).ok_or_else(|| {
            let names: Vec<&str> = self.inner.clips.iter().map(|c| c.name.as_str()).collect();
            JsError::new(&format!("no clip named {name:?}; this character has {names:?}"))
        })
    }
}

fn flatten(v: &[glam::Vec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

/// Symmetric surface distance between two triangle meshes (xyz positions, triangle indices),
/// from `samples` seeded points on each: `{ mean, hausdorff }` in model units.
///
/// Throws when indices are out of range or either mesh has no area.
#[wasm_bindgen(js_name = surfaceDistance)]
pub fn surface_distance(
    positions_a: &[f32],
    indices_a: &[u32],
    positions_b: &[f32],
    indices_b: &[u32],
    samples: u32,
    seed: u32,
) -> Result<js_sys::Object, JsError> {
    let a = checked_mesh(positions_a, indices_a, "first")?;
    let b = checked_mesh(positions_b, indices_b, "second")?;
    let d = crate::metrics::surface_distance((&a, indices_a), (&b, indices_b), samples as usize, seed as u64)
        .ok_or_else(|| JsError::new("surfaceDistance: a mesh has no triangle of positive area"))?;
    let out = js_sys::Object::new();
    js_sys::Reflect::set(&out, &"mean".into(), &f64::from(d.mean).into()).map_err(|_| JsError::new("Reflect.set"))?;
    js_sys::Reflect::set(&out, &"hausdorff".into(), &f64::from(d.hausdorff).into())
        .map_err(|_| JsError::new("Reflect.set"))?;
    Ok(out)
}

/// Length of the bounding-box diagonal of xyz `positions`.
#[wasm_bindgen(js_name = boundsDiagonal)]
pub fn bounds_diagonal(positions: &[f32]) -> f64 {
    let points: Vec<glam::Vec3> = positions.chunks_exact(3).map(glam::Vec3::from_slice).collect();
    crate::metrics::bounds_diagonal(&points) as f64
}

fn checked_mesh(positions: &[f32], indices: &[u32], which: &str) -> Result<Vec<glam::Vec3>, JsError> {
    if positions.len() % 3 != 0 || indices.len() % 3 != 0 {
        return Err(JsError::new(&format!("surfaceDistance: the {which} mesh's arrays are not xyz / triangle lists")));
    }
    let count = positions.len() / 3;
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= count) {
        return Err(JsError::new(&format!("surfaceDistance: the {which} mesh has index {bad} but {count} vertices")));
    }
    Ok(positions.chunks_exact(3).map(glam::Vec3::from_slice).collect())
}
