//! The renderer's WGSL (`skin.wgsl`, `crowd.wgsl`, `mipmap.wgsl`, `difference.wgsl`, `flip.wgsl`), checked without a GPU: it parses and
//! validates with naga (what wgpu runs on it), every entry point translates to GLSL ES 3.00 for
//! WebGL2, and each uniform struct has the size of its `#[repr(C)]` Rust mirror (naga's layouter
//! gives WGSL's size).

use clod_viewer::render::crowd::{InstanceRaw, INSTANCE_OFFSETS};
use clod_viewer::render::difference::{AreaRaw, DIFFERENCE_WGSL};
use clod_viewer::render::flip::{FlipKernelsRaw, FLIP_WGSL};
use clod_viewer::render::mipmap::MIPMAP_WGSL;
use clod_viewer::render::uniforms::{CROWD_WGSL, MAX_MORPH_TARGETS, MIRRORS, SKIN_WGSL};
use naga::back::glsl;
use naga::valid::{Capabilities, ValidationFlags, Validator};

fn parse_and_validate(source: &str) -> (naga::Module, naga::valid::ModuleInfo) {
    let module =
        naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
    // WebGL2 and baseline WebGPU: no optional capabilities.
    let info = Validator::new(ValidationFlags::all(), Capabilities::empty())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
    (module, info)
}

/// The entry points of a validated `source`, sorted.
fn entry_points(source: &str) -> Vec<String> {
    let (module, _) = parse_and_validate(source);
    let mut names: Vec<String> = module.entry_points.iter().map(|e| e.name.clone()).collect();
    names.sort();
    names
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn skin_shader_validates_and_has_the_entry_points_the_renderer_binds() {
    assert_eq!(
        entry_points(SKIN_WGSL),
        [
            "fs_bone",
            "fs_main",
            "fs_wire",
            "vs_bone",
            "vs_geomorph",
            "vs_level",
            "vs_wire_geomorph",
            "vs_wire_level"
        ]
    );
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn skin_shader_translates_to_webgl2_glsl() {
    translates_to_webgl2_glsl(SKIN_WGSL);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn crowd_shader_validates_translates_and_reads_the_instance_records_rust_writes() {
    let names = entry_points(CROWD_WGSL);
    for entry in ["fs_crowd", "fs_ground", "vs_crowd_geomorph", "vs_crowd_level", "vs_ground"] {
        assert!(names.iter().any(|n| n == entry), "{entry} in {names:?}");
    }
    translates_to_webgl2_glsl(CROWD_WGSL);
    // `CrowdInstance`'s members sit at the offsets the instance vertex layout reads from each
    // `InstanceRaw`, and the struct is as large as the record.
    let (module, _) = parse_and_validate(CROWD_WGSL);
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    let (handle, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some("CrowdInstance"))
        .expect("struct CrowdInstance");
    let naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("CrowdInstance is a struct") };
    let offsets: Vec<u64> = members.iter().map(|m| u64::from(m.offset)).collect();
    assert_eq!(offsets, INSTANCE_OFFSETS);
    assert_eq!(*span as usize, std::mem::size_of::<InstanceRaw>());
    assert_eq!(layouter[handle].size as usize, std::mem::size_of::<InstanceRaw>());
    // The instance attributes take locations 14 and 15, after the level's vertices and morph rows
    // (0..=13): WebGL2 guarantees 16 vertex attributes.
    let locations: Vec<u32> = members
        .iter()
        .filter_map(|m| match m.binding {
            Some(naga::Binding::Location { location, .. }) => Some(location),
            _ => None,
        })
        .collect();
    assert_eq!(locations, [14, 15]);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn mipmap_shader_validates_and_translates_to_webgl2_glsl() {
    assert_eq!(entry_points(MIPMAP_WGSL), ["fs_mip", "vs_mip"]);
    translates_to_webgl2_glsl(MIPMAP_WGSL);
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn difference_shader_validates_translates_and_matches_its_uniform_mirror() {
    assert_eq!(entry_points(DIFFERENCE_WGSL), ["fs_difference", "vs_difference"]);
    translates_to_webgl2_glsl(DIFFERENCE_WGSL);
    let (module, _) = parse_and_validate(DIFFERENCE_WGSL);
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    let area = module.types.iter().find(|(_, t)| t.name.as_deref() == Some("Area")).expect("struct Area");
    assert_eq!(layouter[area.0].size as usize, std::mem::size_of::<AreaRaw>());
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn flip_shader_validates_translates_and_matches_its_kernel_mirror() {
    assert_eq!(entry_points(FLIP_WGSL), ["fs_error", "fs_horizontal", "vs_flip"]);
    translates_to_webgl2_glsl(FLIP_WGSL);
    let (module, _) = parse_and_validate(FLIP_WGSL);
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    let kernels =
        module.types.iter().find(|(_, t)| t.name.as_deref() == Some("Kernels")).expect("struct Kernels");
    assert_eq!(layouter[kernels.0].size as usize, std::mem::size_of::<FlipKernelsRaw>());
}

/// Every entry point of `source` translates to GLSL ES 3.00, as wgpu does for WebGL2.
fn translates_to_webgl2_glsl(source: &str) {
    let (module, info) = parse_and_validate(source);
    let options = glsl::Options {
        version: glsl::Version::Embedded { version: 300, is_webgl: true },
        ..glsl::Options::default()
    };
    for entry in &module.entry_points {
        let pipeline = glsl::PipelineOptions {
            shader_stage: entry.stage,
            entry_point: entry.name.clone(),
            multiview: None,
        };
        let mut out = String::new();
        let mut writer = glsl::Writer::new(
            &mut out,
            &module,
            &info,
            &options,
            &pipeline,
            naga::proc::BoundsCheckPolicies::default(),
        )
        .unwrap_or_else(|e| panic!("{}: {e}", entry.name));
        writer.write().unwrap_or_else(|e| panic!("{}: {e}", entry.name));
        assert!(out.starts_with("#version 300 es"), "{}", entry.name);
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn uniform_structs_match_their_rust_mirrors() {
    let (module, _) = parse_and_validate(SKIN_WGSL);
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    for (name, rust_size) in MIRRORS {
        let (handle, _) = module
            .types
            .iter()
            .find(|(_, ty)| ty.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("skin.wgsl has no struct {name}"));
        assert_eq!(layouter[handle].size as usize, rust_size, "size of {name} in WGSL vs its Rust mirror");
    }
}

#[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn morph_target_cap_is_the_same_in_rust_and_wgsl() {
    let (module, _) = parse_and_validate(SKIN_WGSL);
    let targets = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some("MAX_MORPH_TARGETS"))
        .map(|(_, c)| &module.global_expressions[c.init])
        .expect("skin.wgsl declares MAX_MORPH_TARGETS");
    assert_eq!(*targets, naga::Expression::Literal(naga::Literal::U32(MAX_MORPH_TARGETS as u32)));
}
