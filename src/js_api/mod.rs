//! The JavaScript API (wasm-bindgen), identical in the browser and in node.
//!
//! Every fallible call returns `Result<_, JsError>`, which wasm-bindgen turns into a thrown
//! JavaScript `Error` whose message names the problem; nothing here panics on user input.
//! Typed arrays are copies: JavaScript may keep them after the `Character` is freed.

pub mod attributes;
pub mod build_options;
pub mod link;
pub mod read;
#[cfg(test)]
mod samples;
pub mod viewer_settings;
pub mod viewer_state;

use std::rc::Rc;

use wasm_bindgen::prelude::*;

use crate::character::Character as CoreCharacter;
use crate::clod::{self, ClodOptions};
use crate::import;
use build_options::BuildOptions;

/// A Rust resolver over a JS `resolve(name) → Uint8Array | ArrayBuffer | null` (none when
/// `resolve` is `None`), asking it for a URI's path and then for its last segment
/// ([`crate::import::by_path_or_name`]): a `.gltf`'s files dropped with it are found by name.
pub fn resolver(resolve: Option<&js_sys::Function>) -> impl FnMut(&str) -> Option<Vec<u8>> + '_ {
    crate::import::by_path_or_name(move |name: &str| {
        let value = resolve?.call1(&JsValue::NULL, &JsValue::from_str(name)).ok()?;
        let bytes =
            value.is_instance_of::<js_sys::Uint8Array>() || value.is_instance_of::<js_sys::ArrayBuffer>();
        bytes.then(|| js_sys::Uint8Array::new(&value).to_vec())
    })
}

/// The type of `buildClod`'s options in the generated `.d.ts` (the fields of
/// [`BuildOptions`]; `tests/js/dts.test.mjs` checks it against their serialization).
#[wasm_bindgen(typescript_custom_section)]
const BUILD_OPTIONS_TS: &str = r#"
/** `buildClod(options)` and `buildClodBytes(options)`: every key optional; an unknown key or a bad value throws. */
export interface BuildOptions {
  /** The simplification pose: `'multi'` (default: quadrics over frames of every clip), `'mid-clip'`, `'bind'`, or one clip frame. */
  pose?: 'multi' | 'mid-clip' | 'bind' | { clip: string; time: number };
  /** Decreasing triangle counts of the levels (whole numbers ≥ 1). */
  levels?: number[];
  /** `'full'` (default: optimal placement) or `'halfedge'`. */
  mode?: 'full' | 'halfedge';
  /** Skin weights of new vertices: `'blend'` (default) or `'survivor'`. */
  weights?: 'blend' | 'survivor';
  /** `'strict'` (default: cheapest collapse first) or `'passes'` (batched, faster). */
  schedule?: 'strict' | 'passes';
  /** The floor, a positive fraction of the bounding-box diagonal (default 0.05; `Infinity`: as far as the topology allows). */
  maxError?: number;
  /** Called with fractions from 0 to 1. */
  onProgress?: (fraction: number) => void;
}
"#;

/// Installs the panic hook that prints Rust panics to the console (called once on load).
#[wasm_bindgen(start)]
pub fn start() {
    console_error_panic_hook::set_once();
}

/// A skinned glTF character loaded into the core.
#[wasm_bindgen]
pub struct Character {
    inner: Rc<CoreCharacter>,
}

#[wasm_bindgen]
impl Character {
    /// Loads a binary glTF (`.glb`).
    ///
    /// Throws an `Error` naming the problem when the bytes are not a usable skinned glTF.
    #[wasm_bindgen(js_name = fromGlb)]
    pub fn from_glb(bytes: &[u8]) -> Result<Character, JsError> {
        let inner = import::from_glb(bytes).map_err(|e| JsError::new(&e.to_string()))?;
        Ok(Character { inner: Rc::new(inner) })
    }

    /// Loads a JSON glTF (`.gltf`); `resolve(uri)` returns the bytes of an external buffer or
    /// image as a `Uint8Array`, or `null`/`undefined` when it has none. It is asked for the URI's
    /// path (percent-decoded), and when it has none, for the path's last segment, the name a file
    /// dropped with the `.gltf` keeps (`textures/skin.png`, then `skin.png`). `data:` URIs need
    /// no resolver.
    ///
    /// Throws an `Error` naming the problem (including a URI the resolver could not supply).
    #[wasm_bindgen(js_name = fromGltf)]
    pub fn from_gltf(json: &[u8], resolve: &js_sys::Function) -> Result<Character, JsError> {
        let mut resolver = resolver(Some(resolve));
        let inner = import::from_gltf(json, &mut resolver).map_err(|e| JsError::new(&e.to_string()))?;
        Ok(Character { inner: Rc::new(inner) })
    }

    /// Loads either form, a `.glb` or a `.gltf`, telling them apart by the first bytes (the GLB
    /// magic `glTF`); `resolve(uri)` supplies a `.gltf`'s external files as for
    /// [`Character::from_gltf`] (a `.glb` with everything inside never calls it). `draco`
    /// (optional) decodes Draco streams: the `decode` of the separate Draco module
    /// (`www/pkg-draco/`), which a build without the built-in decoder (the viewer page's) needs for
    /// the files [`uses_draco`] finds.
    ///
    /// Throws an `Error` naming the problem.
    #[wasm_bindgen(js_name = fromBytes)]
    pub fn from_bytes(
        bytes: &[u8],
        resolve: &js_sys::Function,
        #[wasm_bindgen(
            unchecked_param_type = "((stream: Uint8Array, request: Uint32Array) => Uint8Array) | undefined"
        )]
        draco: JsValue,
    ) -> Result<Character, JsError> {
        let mut resolver = resolver(Some(resolve));
        let draco = draco.dyn_into::<js_sys::Function>().ok();
        let mut decoder = draco.as_ref().map(draco_decoder);
        let inner = import::from_bytes_with(
            bytes,
            &mut resolver,
            decoder.as_mut().map(|d| d as &mut import::DracoDecoder),
        )
        .map_err(|e| JsError::new(&e.to_string()))?;
        Ok(Character { inner: Rc::new(inner) })
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

    /// Number of morph targets: every primitive's targets count separately (see docs/import.md).
    #[wasm_bindgen(getter, js_name = morphTargetCount)]
    pub fn morph_target_count(&self) -> usize {
        self.inner.morph_targets.len()
    }

    /// Morph weights (one per target) of clip `clipName` at `timeSeconds` (looping), over the
    /// default weights of the file's nodes and meshes.
    ///
    /// Throws when there is no clip of that name or the time is not a finite number.
    #[wasm_bindgen(js_name = morphWeights)]
    pub fn morph_weights(&self, clip_name: &str, time_seconds: f64) -> Result<Vec<f32>, JsError> {
        let time = finite_time(time_seconds)?;
        Ok(self.inner.morph_weights_at(self.find_clip(clip_name)?, time))
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

    /// The material of every triangle: an index into the file's materials, or `0xFFFFFFFF` for
    /// glTF's default material.
    #[wasm_bindgen(js_name = triangleMaterials)]
    pub fn triangle_materials(&self) -> Vec<u32> {
        crate::clod::material_ids(&self.inner)
    }

    /// Bind-space positions, xyz per vertex.
    #[wasm_bindgen(js_name = bindPositions)]
    pub fn bind_positions(&self) -> Vec<f32> {
        flatten(&self.inner.mesh.positions)
    }

    /// Unit bind-space normals, xyz per vertex (computed from the triangles when the file has
    /// none).
    pub fn normals(&self) -> Vec<f32> {
        flatten(&self.inner.mesh.normals)
    }

    /// The texture coordinates the base colour texture samples, uv per vertex (zeros on
    /// primitives without a texture or without that set), or `undefined` when no primitive has
    /// any: texture coordinates no texture samples draw nothing and are not imported.
    pub fn uvs(&self) -> Option<Vec<f32>> {
        self.inner.mesh.uvs.as_ref().map(|uvs| uvs.iter().flat_map(|uv| uv.to_array()).collect())
    }

    /// CPU-skinned positions (xyz per vertex, whole mesh) of clip `clipName` at `timeSeconds`
    /// (looping), the clip's morph weights applied before skinning.
    ///
    /// Throws when there is no clip of that name or the time is not a finite number.
    #[wasm_bindgen(js_name = skinnedPositions)]
    pub fn skinned_positions(&self, clip_name: &str, time_seconds: f64) -> Result<Vec<f32>, JsError> {
        let time = finite_time(time_seconds)?;
        let clip = self.find_clip(clip_name)?;
        Ok(flatten(&self.inner.clip_skinned_positions(clip, time)))
    }

    /// Builds the articulated progressive mesh and its discrete levels.
    ///
    /// `options` (all optional): `pose`: `'multi'` (default: quadrics over frames of every clip),
    /// `'mid-clip'` (the middle of the first clip), `'bind'` or `{ clip, time }`;
    /// `levels`: decreasing triangle counts; `mode`: `'full'` (default) or `'halfedge'`;
    /// `weights`: `'blend'` (default) or `'survivor'` for the skin weights of new vertices;
    /// `schedule`: `'strict'` (default: always the cheapest collapse next) or `'passes'` (batched
    /// collapse passes, faster, see `Schedule`);
    /// `maxError`: the floor, stop before a collapse whose error exceeds this fraction of the
    /// bounding-box diagonal (default 0.05; `Infinity` goes as far as the topology allows);
    /// `onProgress(fraction)`: called with fractions from 0 to 1.
    ///
    /// Throws on malformed options (naming the option) or a mesh that cannot be simplified.
    #[wasm_bindgen(js_name = buildClod)]
    pub fn build_clod(
        &self,
        #[wasm_bindgen(unchecked_param_type = "BuildOptions | undefined")] options: JsValue,
    ) -> Result<Clod, JsError> {
        let (options, on_progress) = parse_clod_options(options, &self.inner)?;
        let started = now_ms();
        let mut progress = |fraction: f32| {
            if let Some(f) = &on_progress {
                let _ = f.call1(&JsValue::NULL, &JsValue::from_f64(fraction as f64));
            }
        };
        let built =
            clod::build(&self.inner, &options, &mut progress).map_err(|e| JsError::new(&e.to_string()))?;
        Ok(Clod { character: Rc::clone(&self.inner), clod: built, build_ms: now_ms() - started })
    }

    /// Builds the chain like [`Character::build_clod`] and returns it encoded (the format of
    /// `clod::bytes`, starting with `"CLOD"`), for a Web Worker to transfer to the page, which
    /// decodes it against its own import of the same file.
    ///
    /// `options` are those of `buildClod`; `onProgress(fraction)` (optional, or `options.onProgress`
    /// when absent) is called with non-decreasing fractions from 0, ending with exactly 1 once the
    /// bytes are ready.
    ///
    /// Throws on malformed options, an `onProgress` that is not a function, or a mesh that cannot
    /// be simplified.
    #[wasm_bindgen(js_name = buildClodBytes)]
    pub fn build_clod_bytes(
        &self,
        #[wasm_bindgen(unchecked_param_type = "BuildOptions | undefined")] options: JsValue,
        #[wasm_bindgen(unchecked_param_type = "((fraction: number) => void) | undefined")]
        on_progress: JsValue,
    ) -> Result<Vec<u8>, JsError> {
        let (options, from_options) = parse_clod_options(options, &self.inner)?;
        let on_progress = if on_progress.is_undefined() || on_progress.is_null() {
            from_options
        } else {
            Some(
                on_progress
                    .dyn_into::<js_sys::Function>()
                    .map_err(|_| JsError::new("onProgress must be a function"))?,
            )
        };
        let report = |fraction: f64| {
            if let Some(f) = &on_progress {
                let _ = f.call1(&JsValue::NULL, &JsValue::from_f64(fraction));
            }
        };
        // The build reports 0..1; encoding is one linear pass over the chain, a few percent of
        // the build's time, so it gets the last 5 % and the final 1 means "bytes ready".
        const BUILD_SHARE: f64 = 0.95;
        let mut progress = |fraction: f32| report(f64::from(fraction) * BUILD_SHARE);
        let built =
            clod::build(&self.inner, &options, &mut progress).map_err(|e| JsError::new(&e.to_string()))?;
        let bytes = clod::bytes::encode(&built);
        report(1.0);
        Ok(bytes)
    }
}

impl Character {
    fn find_clip(&self, name: &str) -> Result<&crate::animation::Clip, JsError> {
        self.inner.clip(name).ok_or_else(|| unknown_clip(&self.inner, name))
    }
}

/// An articulated progressive mesh: discrete levels with ancestor tables, and any triangle count
/// in between.
#[wasm_bindgen]
pub struct Clod {
    character: Rc<CoreCharacter>,
    clod: clod::Clod,
    build_ms: f64,
}

#[wasm_bindgen]
impl Clod {
    /// Wall-clock milliseconds the build took (progressive mesh, levels and tables).
    #[wasm_bindgen(getter, js_name = buildMs)]
    pub fn build_ms(&self) -> f64 {
        self.build_ms
    }

    /// Number of discrete levels, finest first.
    #[wasm_bindgen(getter, js_name = levelCount)]
    pub fn level_count(&self) -> usize {
        self.clod.levels.len()
    }

    /// Why the coarsest level has more triangles than the build asked for, as a sentence
    /// ("the levels stop at 988 of 3840 triangles (26 %): ..."); `undefined` when the build
    /// reached its last requested count.
    #[wasm_bindgen(getter, js_name = stoppedShort)]
    pub fn stopped_short(&self) -> Option<String> {
        self.clod.stopped_short().map(|s| s.to_string())
    }

    /// Bytes used by all ancestor tables.
    #[wasm_bindgen(getter, js_name = ancestorTableBytes)]
    pub fn ancestor_table_bytes(&self) -> usize {
        self.clod.ancestor_table_bytes()
    }

    /// Level `i`: `{ triangleCount, vertexCount, error, indices: Uint32Array, positions:
    /// Float32Array }`, positions in the simplification pose, error in model units.
    ///
    /// Throws when `i` is out of range.
    pub fn level(&self, i: usize) -> Result<js_sys::Object, JsError> {
        let level = self.level_ref(i)?;
        let out = js_sys::Object::new();
        set(&out, "triangleCount", JsValue::from(level.triangle_count() as u32))?;
        set(&out, "vertexCount", JsValue::from(level.vertices.len() as u32))?;
        set(&out, "error", JsValue::from_f64(level.error as f64))?;
        set(&out, "indices", js_sys::Uint32Array::from(level.indices.as_slice()).into())?;
        let positions = flatten(&self.clod.level_pose_positions(i));
        set(&out, "positions", js_sys::Float32Array::from(positions.as_slice()).into())?;
        Ok(out)
    }

    /// For every vertex of level `i`, the index of its ancestor vertex in level `i + 1`.
    ///
    /// Throws when `i` is not a level with a coarser one after it.
    pub fn ancestors(&self, i: usize) -> Result<Vec<u32>, JsError> {
        if i + 1 >= self.clod.levels.len() {
            return Err(JsError::new(&format!(
                "ancestors({i}): levels 0..{} have a coarser level after them",
                self.clod.levels.len().saturating_sub(1)
            )));
        }
        Ok(self.clod.levels[i].ancestors.clone())
    }

    /// The continuous level with at most `triangles` triangles (the coarsest if fewer are
    /// impossible): `{ indices, positions, bindPositions }` (simplification pose and bind space).
    #[wasm_bindgen(js_name = meshAt)]
    pub fn mesh_at(&self, triangles: usize) -> Result<js_sys::Object, JsError> {
        let pm = &self.clod.apm.pm;
        let mut cursor = pm.cursor();
        cursor.set_triangle_count(triangles);
        let vertices = cursor.vertices();
        let positions: Vec<f32> =
            vertices.iter().flat_map(|&v| pm.positions[v as usize].to_array()).collect();
        let bind: Vec<f32> =
            vertices.iter().flat_map(|&v| self.clod.apm.bind_positions[v as usize].to_array()).collect();
        let out = js_sys::Object::new();
        set(&out, "indices", js_sys::Uint32Array::from(cursor.indices()).into())?;
        set(&out, "positions", js_sys::Float32Array::from(positions.as_slice()).into())?;
        set(&out, "bindPositions", js_sys::Float32Array::from(bind.as_slice()).into())?;
        Ok(out)
    }

    /// CPU-skinned positions (xyz per vertex) of level `i` in clip `clipName` at `timeSeconds`,
    /// the clip's morph weights applied before skinning.
    ///
    /// Throws for an unknown level or clip, or a non-finite time.
    #[wasm_bindgen(js_name = levelSkinnedPositions)]
    pub fn level_skinned_positions(
        &self,
        i: usize,
        clip_name: &str,
        time_seconds: f64,
    ) -> Result<Vec<f32>, JsError> {
        self.level_ref(i)?;
        let time = finite_time(time_seconds)?;
        let clip = self.character.clip(clip_name).ok_or_else(|| unknown_clip(&self.character, clip_name))?;
        let skin = self.character.skin_matrices(&self.character.pose_at(clip, time));
        let weights = self.character.morph_weights_at(clip, time);
        Ok(flatten(&self.clod.level_morphed_skinned_positions(i, &skin, &weights)))
    }
}

impl Clod {
    fn level_ref(&self, i: usize) -> Result<&clod::LodLevel, JsError> {
        self.clod.levels.get(i).ok_or_else(|| {
            JsError::new(&format!("level {i} does not exist; there are {}", self.clod.levels.len()))
        })
    }
}

/// Whether `bytes` (a `.glb` or `.gltf`) declare Draco-compressed geometry: a page whose build has
/// no built-in Draco decoder then loads the separate module (`www/pkg-draco/`) and passes its
/// `decode` to `Character.fromBytes` or `Viewer.create`.
#[wasm_bindgen(js_name = usesDraco)]
pub fn uses_draco(bytes: &[u8]) -> bool {
    import::uses_draco(bytes)
}

/// A Draco decoder over the separate module's `decode(stream, request) → answer` (see
/// `crates/clod-draco`): the request and the answer cross as words and bytes.
pub fn draco_decoder(
    decode: &js_sys::Function,
) -> impl FnMut(&[u8], &clod_draco::Request) -> Result<clod_draco::Decoded, clod_draco::DecodeError> + '_ {
    move |stream, request| {
        let stream = js_sys::Uint8Array::from(stream);
        let words = js_sys::Uint32Array::from(request.to_words().as_slice());
        let answer = decode
            .call2(&JsValue::NULL, &stream, &words)
            .ok()
            .and_then(|a| a.dyn_into::<js_sys::Uint8Array>().ok())
            .ok_or_else(|| clod_draco::DecodeError::Invalid("the Draco module did not answer".into()))?;
        clod_draco::read_answer(&answer.to_vec()).map_err(clod_draco::DecodeError::Invalid)?
    }
}

/// Reads `buildClod`'s options object (see [`Character::build_clod`]): the core's options and
/// the progress callback, if any.
fn parse_clod_options(
    options: JsValue,
    character: &CoreCharacter,
) -> Result<(ClodOptions, Option<js_sys::Function>), JsError> {
    let options: BuildOptions = if options.is_undefined() || options.is_null() {
        BuildOptions::default()
    } else {
        read::read("buildClod", options, "{ levels: [4000, 1000], pose: 'multi' }")
            .map_err(|e| JsError::new(&e))?
    };
    let clod = options.clod_options(character).map_err(|e| JsError::new(&e))?;
    Ok((clod, options.on_progress.map(|c| c.0)))
}

/// `time_seconds` as `f32`, or the error every timed call throws.
fn finite_time(time_seconds: f64) -> Result<f32, JsError> {
    if !time_seconds.is_finite() {
        return Err(JsError::new(&format!("time must be a finite number of seconds, got {time_seconds}")));
    }
    Ok(time_seconds as f32)
}

fn unknown_clip(character: &CoreCharacter, name: &str) -> JsError {
    JsError::new(&unknown_clip_message(character, name))
}

/// "no clip named "Dance"; this character has ["Walk", "Wave"]".
fn unknown_clip_message(character: &CoreCharacter, name: &str) -> String {
    let names: Vec<&str> = character.clips.iter().map(|c| c.name.as_str()).collect();
    format!("no clip named {name:?}; this character has {names:?}")
}

fn set(object: &js_sys::Object, key: &str, value: JsValue) -> Result<(), JsError> {
    js_sys::Reflect::set(object, &JsValue::from_str(key), &value)
        .map(|_| ())
        .map_err(|_| JsError::new("cannot build result object"))
}

/// Milliseconds from `performance.now()` (browser and node); 0 where there is none.
fn now_ms() -> f64 {
    let performance =
        js_sys::Reflect::get(&js_sys::global(), &"performance".into()).unwrap_or(JsValue::UNDEFINED);
    js_sys::Reflect::get(&performance, &"now".into())
        .ok()
        .and_then(|f| f.dyn_into::<js_sys::Function>().ok())
        .and_then(|f| f.call0(&performance).ok())
        .and_then(|t| t.as_f64())
        .unwrap_or(0.0)
}

fn flatten(v: &[glam::Vec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

/// Symmetric surface distance between two triangle meshes (xyz positions, triangle indices),
/// from `samples` seeded points on each: `{ mean, meanFromA, meanFromB, hausdorff }` in model
/// units, `mean` being the mean of the halves (A's samples from B: what B misses; B's from A:
/// where B strays).
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
    js_sys::Reflect::set(&out, &"mean".into(), &f64::from(d.mean).into())
        .map_err(|_| JsError::new("Reflect.set"))?;
    for (key, value) in
        [("meanFromA", d.mean_from_a), ("meanFromB", d.mean_from_b), ("hausdorff", d.hausdorff)]
    {
        js_sys::Reflect::set(&out, &key.into(), &f64::from(value).into())
            .map_err(|_| JsError::new("Reflect.set"))?;
    }
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
        return Err(JsError::new(&format!(
            "surfaceDistance: the {which} mesh's arrays are not xyz / triangle lists"
        )));
    }
    let count = positions.len() / 3;
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= count) {
        return Err(JsError::new(&format!(
            "surfaceDistance: the {which} mesh has index {bad} but {count} vertices"
        )));
    }
    Ok(positions.chunks_exact(3).map(glam::Vec3::from_slice).collect())
}

/// Bytes of this wasm instance's linear memory. Memory only grows, so after a build this is the
/// peak the build needed (plus whatever the instance held before); `bench/scaling.mjs` reports
/// it per character size.
#[cfg(target_arch = "wasm32")]
#[wasm_bindgen(js_name = wasmMemoryBytes)]
pub fn wasm_memory_bytes() -> f64 {
    (core::arch::wasm32::memory_size::<0>() * 65_536) as f64
}
