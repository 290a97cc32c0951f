//! What the renderer asks of a device: Vulkan 1.3, the features it cannot run
//! without, the optional ones it uses where the device has them, and the device
//! extensions those need. One list, read when the renderer makes its own device
//! ([`super::Context::new`]) and when a caller makes one for an embedded field
//! (`crate::embed`). `GRASS_FAULT=missing-feature:<name>` takes any of them away
//! ([`super::fault`]).

use super::fault::feature_removed;
use ash::{ext, khr, vk};
use std::ffi::CStr;

/// What a device lacks of what the renderer needs, by Vulkan name.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{device} lacks what the grass renderer needs: {}", missing.join(", "))]
pub struct Missing {
    /// The device's name.
    pub device: String,
    /// Each thing missing: "Vulkan 1.3 (the device has 1.2)", "feature
    /// tessellationShader", "format D32_SFLOAT as a depth attachment", ...
    pub missing: Vec<String>,
}

/// The features to enable on a device for the renderer: every required one, and the
/// optional ones the device has. Callers making their own device may add theirs to
/// the public structs before [`DeviceFeatures::enable`].
pub struct DeviceFeatures {
    /// Vulkan 1.0 features: tessellationShader, multiDrawIndirect, fillModeNonSolid;
    /// pipelineStatisticsQuery and shaderInt64 where the device has them.
    pub core: vk::PhysicalDeviceFeatures,
    /// Vulkan 1.1 features: shaderDrawParameters with mesh shaders.
    pub v11: vk::PhysicalDeviceVulkan11Features<'static>,
    /// Vulkan 1.2 features: vulkanMemoryModel (and its device scope);
    /// shaderBufferInt64Atomics where the device has it.
    pub v12: vk::PhysicalDeviceVulkan12Features<'static>,
    /// Vulkan 1.3 features: dynamicRendering, synchronization2, maintenance4.
    pub v13: vk::PhysicalDeviceVulkan13Features<'static>,
    /// `VK_EXT_mesh_shader`'s meshShader, when [`Self::mesh_shader`] is `Ok`.
    pub mesh: vk::PhysicalDeviceMeshShaderFeaturesEXT<'static>,
    /// `Ok` when the mesh path is enabled (`VK_EXT_mesh_shader` with mesh stages,
    /// shaderDrawParameters and the limits `shared::meshlet` declares); else why not.
    pub mesh_shader: Result<(), String>,
    /// `Ok` when 64-bit integers and 64-bit storage-buffer atomics are enabled (the
    /// compute rasterizer's visibility buffer, `shared::raster`); else what is missing.
    pub int64_atomics: Result<(), String>,
    /// `VK_KHR_pipeline_executable_properties`' pipelineExecutableInfo, enabled where
    /// [`STATS_VARIABLE`] asks for the compute pipelines' statistics and the device
    /// has it.
    pub executables: vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR<'static>,
    /// The same features in per-feature structs, for [`Self::enable_beside`].
    beside: Beside,
}

/// The renderer's Vulkan 1.1 to 1.3 features in the structs of the extensions that
/// brought them, and the core features merged with another program's
/// ([`DeviceFeatures::enable_beside`]).
#[derive(Default)]
struct Beside {
    core: vk::PhysicalDeviceFeatures,
    draw_parameters: vk::PhysicalDeviceShaderDrawParametersFeatures<'static>,
    memory_model: vk::PhysicalDeviceVulkanMemoryModelFeatures<'static>,
    int64_atomics: vk::PhysicalDeviceShaderAtomicInt64Features<'static>,
    dynamic_rendering: vk::PhysicalDeviceDynamicRenderingFeatures<'static>,
    synchronization2: vk::PhysicalDeviceSynchronization2Features<'static>,
    maintenance4: vk::PhysicalDeviceMaintenance4Features<'static>,
}

/// The features the renderer cannot run without, as (name, present) pairs.
fn required(
    core: &vk::PhysicalDeviceFeatures,
    v12: &vk::PhysicalDeviceVulkan12Features,
    v13: &vk::PhysicalDeviceVulkan13Features,
) -> [(&'static str, vk::Bool32); 9] {
    [
        ("tessellationShader", core.tessellation_shader),
        // The draw's motion target is written by the grass and kept by the ground
        // (temporal anti-aliasing): two colour attachments blended differently.
        ("independentBlend", core.independent_blend),
        ("multiDrawIndirect", core.multi_draw_indirect),
        ("fillModeNonSolid", core.fill_mode_non_solid),
        ("vulkanMemoryModel", v12.vulkan_memory_model),
        (
            "vulkanMemoryModelDeviceScope",
            v12.vulkan_memory_model_device_scope,
        ),
        ("dynamicRendering", v13.dynamic_rendering),
        ("synchronization2", v13.synchronization2),
        // A fragment stage may leave some of the outputs before it unread (the views'
        // fragment stages read fewer). Every Vulkan 1.3 device has it.
        ("maintenance4", v13.maintenance4),
    ]
}

/// The device's name as its driver reports it.
pub fn device_name(instance: &ash::Instance, physical: vk::PhysicalDevice) -> String {
    name_of(&unsafe { instance.get_physical_device_properties(physical) })
}

/// The name in a device's `properties`.
pub fn name_of(properties: &vk::PhysicalDeviceProperties) -> String {
    properties
        .device_name_as_c_str()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

impl DeviceFeatures {
    /// What to enable on `physical`, or everything it lacks of the required list.
    pub fn query(instance: &ash::Instance, physical: vk::PhysicalDevice) -> Result<Self, Missing> {
        let props = unsafe { instance.get_physical_device_properties(physical) };
        let mut missing = Vec::new();
        if props.api_version < vk::API_VERSION_1_3 {
            missing.push(format!(
                "Vulkan 1.3 (the device has {}.{})",
                vk::api_version_major(props.api_version),
                vk::api_version_minor(props.api_version)
            ));
        }
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut has = vk::PhysicalDeviceFeatures2::default()
            .push_next(&mut v12)
            .push_next(&mut v13);
        unsafe { instance.get_physical_device_features2(physical, &mut has) };
        let core = has.features;
        missing.extend(
            required(&core, &v12, &v13)
                .into_iter()
                .filter(|(name, have)| *have == vk::FALSE || feature_removed(name))
                .map(|(name, _)| format!("feature {name}")),
        );
        if !missing.is_empty() {
            let device = device_name(instance, physical);
            return Err(Missing { device, missing });
        }
        let mesh_shader = mesh_shader_support(instance, physical);
        let int64_atomics = int64_atomics_support(instance, physical);
        let statistics = core.pipeline_statistics_query == vk::TRUE;
        let executables = std::env::var_os(STATS_VARIABLE).is_some()
            && has_extension(
                instance,
                physical,
                khr::pipeline_executable_properties::NAME,
            );
        Ok(Self {
            core: vk::PhysicalDeviceFeatures::default()
                .tessellation_shader(true)
                .independent_blend(true)
                .multi_draw_indirect(true)
                .fill_mode_non_solid(true)
                .pipeline_statistics_query(statistics)
                .shader_int64(int64_atomics.is_ok()),
            v11: vk::PhysicalDeviceVulkan11Features::default()
                .shader_draw_parameters(mesh_shader.is_ok()),
            v12: vk::PhysicalDeviceVulkan12Features::default()
                .shader_buffer_int64_atomics(int64_atomics.is_ok())
                .vulkan_memory_model(true)
                .vulkan_memory_model_device_scope(true),
            v13: vk::PhysicalDeviceVulkan13Features::default()
                .maintenance4(true)
                .dynamic_rendering(true)
                .synchronization2(true),
            mesh: vk::PhysicalDeviceMeshShaderFeaturesEXT::default()
                .mesh_shader(mesh_shader.is_ok()),
            mesh_shader,
            int64_atomics,
            executables: vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default()
                .pipeline_executable_info(executables),
            beside: Beside::default(),
        })
    }

    /// The device extensions to enable: `VK_EXT_mesh_shader` with the mesh path.
    pub fn extensions(&self) -> Vec<&'static CStr> {
        let mut names = Vec::new();
        if self.mesh_shader.is_ok() {
            names.push(ext::mesh_shader::NAME);
        }
        if self.pipeline_executables() {
            names.push(khr::pipeline_executable_properties::NAME);
        }
        names
    }

    /// The compute pipelines' statistics are asked for and enabled
    /// ([`STATS_VARIABLE`]).
    pub fn pipeline_executables(&self) -> bool {
        self.executables.pipeline_executable_info == vk::TRUE
    }

    /// Pipeline statistics queries are enabled (the grass draw's triangle count).
    pub fn pipeline_statistics(&self) -> bool {
        self.core.pipeline_statistics_query == vk::TRUE
    }

    /// `info` with these features enabled (its `pEnabledFeatures` and feature
    /// structs in its chain; add [`Self::extensions`] to its extension names).
    pub fn enable<'a>(&'a mut self, info: vk::DeviceCreateInfo<'a>) -> vk::DeviceCreateInfo<'a> {
        let executables = self.pipeline_executables();
        let info = info
            .enabled_features(&self.core)
            .push_next(&mut self.v11)
            .push_next(&mut self.v12)
            .push_next(&mut self.v13);
        let info = match self.mesh_shader {
            Ok(()) => info.push_next(&mut self.mesh),
            Err(_) => info,
        };
        if executables {
            info.push_next(&mut self.executables)
        } else {
            info
        }
    }

    /// `info`, whose chain another program already filled (wgpu-hal's
    /// `PhysicalDeviceFeatures::add_to_device_create` chains one struct per extension
    /// and core features through `pEnabledFeatures`), with these features enabled
    /// beside its own: each set in the struct of the chain that holds it (a
    /// per-extension struct or a `Vulkan11/12/13Features`), the rest in structs of
    /// their own pushed onto the chain (a chain may not hold two structs of one type,
    /// nor a per-extension struct beside the `Vulkan1xFeatures` that holds the same
    /// feature), the core features merged with the ones it points at. Add
    /// [`Self::extensions`] to its extension names.
    pub fn enable_beside<'a>(
        &'a mut self,
        info: vk::DeviceCreateInfo<'a>,
    ) -> vk::DeviceCreateInfo<'a> {
        let theirs = unsafe { info.p_enabled_features.as_ref() }.copied();
        self.beside.core = merged(theirs.unwrap_or_default(), &self.core);
        let Self {
            v11,
            v12,
            v13,
            mesh,
            beside,
            ..
        } = self;
        let or = |to: &mut vk::Bool32, from: vk::Bool32| *to |= from;
        // Which of the renderer's structs the chain already covers.
        let (mut draw, mut model, mut int64, mut dynamic, mut sync2, mut m4, mut has_mesh) =
            (false, false, false, false, false, false, false);
        let mut next = info.p_next as *mut vk::BaseOutStructure;
        // SAFETY: each struct of the chain is the type its sType names, and `info`
        // (so its chain) is borrowed mutably for 'a by the caller.
        while !next.is_null() {
            use vk::StructureType as T;
            let (s_type, following) = unsafe { ((*next).s_type, (*next).p_next) };
            let at = next.cast::<u8>();
            unsafe {
                match s_type {
                    T::PHYSICAL_DEVICE_VULKAN_1_1_FEATURES => {
                        let f = &mut *at.cast::<vk::PhysicalDeviceVulkan11Features>();
                        or(&mut f.shader_draw_parameters, v11.shader_draw_parameters);
                        draw = true;
                    }
                    T::PHYSICAL_DEVICE_VULKAN_1_2_FEATURES => {
                        let f = &mut *at.cast::<vk::PhysicalDeviceVulkan12Features>();
                        or(&mut f.vulkan_memory_model, v12.vulkan_memory_model);
                        or(
                            &mut f.vulkan_memory_model_device_scope,
                            v12.vulkan_memory_model_device_scope,
                        );
                        or(
                            &mut f.shader_buffer_int64_atomics,
                            v12.shader_buffer_int64_atomics,
                        );
                        (model, int64) = (true, true);
                    }
                    T::PHYSICAL_DEVICE_VULKAN_1_3_FEATURES => {
                        let f = &mut *at.cast::<vk::PhysicalDeviceVulkan13Features>();
                        or(&mut f.dynamic_rendering, v13.dynamic_rendering);
                        or(&mut f.synchronization2, v13.synchronization2);
                        or(&mut f.maintenance4, v13.maintenance4);
                        (dynamic, sync2, m4) = (true, true, true);
                    }
                    T::PHYSICAL_DEVICE_SHADER_DRAW_PARAMETERS_FEATURES => {
                        let f = &mut *at.cast::<vk::PhysicalDeviceShaderDrawParametersFeatures>();
                        or(&mut f.shader_draw_parameters, v11.shader_draw_parameters);
                        draw = true;
                    }
                    T::PHYSICAL_DEVICE_VULKAN_MEMORY_MODEL_FEATURES => {
                        let f = &mut *at.cast::<vk::PhysicalDeviceVulkanMemoryModelFeatures>();
                        or(&mut f.vulkan_memory_model, v12.vulkan_memory_model);
                        or(
                            &mut f.vulkan_memory_model_device_scope,
                            v12.vulkan_memory_model_device_scope,
                        );
                        model = true;
                    }
                    T::PHYSICAL_DEVICE_SHADER_ATOMIC_INT64_FEATURES => {
                        let f = &mut *at.cast::<vk::PhysicalDeviceShaderAtomicInt64Features>();
                        or(
                            &mut f.shader_buffer_int64_atomics,
                            v12.shader_buffer_int64_atomics,
                        );
                        int64 = true;
                    }
                    T::PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES => {
                        let f = &mut *at.cast::<vk::PhysicalDeviceDynamicRenderingFeatures>();
                        or(&mut f.dynamic_rendering, v13.dynamic_rendering);
                        dynamic = true;
                    }
                    T::PHYSICAL_DEVICE_SYNCHRONIZATION_2_FEATURES => {
                        let f = &mut *at.cast::<vk::PhysicalDeviceSynchronization2Features>();
                        or(&mut f.synchronization2, v13.synchronization2);
                        sync2 = true;
                    }
                    T::PHYSICAL_DEVICE_MAINTENANCE_4_FEATURES => {
                        let f = &mut *at.cast::<vk::PhysicalDeviceMaintenance4Features>();
                        or(&mut f.maintenance4, v13.maintenance4);
                        m4 = true;
                    }
                    T::PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT => {
                        let f = &mut *at.cast::<vk::PhysicalDeviceMeshShaderFeaturesEXT>();
                        or(&mut f.mesh_shader, mesh.mesh_shader);
                        has_mesh = true;
                    }
                    _ => {}
                }
            }
            next = following;
        }
        let mut info = info.enabled_features(&beside.core);
        let on = |flag: vk::Bool32| flag == vk::TRUE;
        if !draw && on(v11.shader_draw_parameters) {
            beside.draw_parameters.shader_draw_parameters = vk::TRUE;
            info = info.push_next(&mut beside.draw_parameters);
        }
        if !model {
            beside.memory_model.vulkan_memory_model = v12.vulkan_memory_model;
            beside.memory_model.vulkan_memory_model_device_scope =
                v12.vulkan_memory_model_device_scope;
            info = info.push_next(&mut beside.memory_model);
        }
        if !int64 && on(v12.shader_buffer_int64_atomics) {
            beside.int64_atomics.shader_buffer_int64_atomics = vk::TRUE;
            info = info.push_next(&mut beside.int64_atomics);
        }
        if !dynamic {
            beside.dynamic_rendering.dynamic_rendering = v13.dynamic_rendering;
            info = info.push_next(&mut beside.dynamic_rendering);
        }
        if !sync2 {
            beside.synchronization2.synchronization2 = v13.synchronization2;
            info = info.push_next(&mut beside.synchronization2);
        }
        if !m4 {
            beside.maintenance4.maintenance4 = v13.maintenance4;
            info = info.push_next(&mut beside.maintenance4);
        }
        if !has_mesh && on(mesh.mesh_shader) {
            info = info.push_next(mesh);
        }
        info
    }
}

/// Every core feature on in `theirs` or `ours`.
fn merged(
    theirs: vk::PhysicalDeviceFeatures,
    ours: &vk::PhysicalDeviceFeatures,
) -> vk::PhysicalDeviceFeatures {
    const N: usize = size_of::<vk::PhysicalDeviceFeatures>() / size_of::<vk::Bool32>();
    let mut out = theirs;
    // SAFETY: VkPhysicalDeviceFeatures is N VkBool32s and nothing else.
    let (to, from) = unsafe {
        (
            std::slice::from_raw_parts_mut((&raw mut out).cast::<vk::Bool32>(), N),
            std::slice::from_raw_parts(
                (ours as *const vk::PhysicalDeviceFeatures).cast::<vk::Bool32>(),
                N,
            ),
        )
    };
    for (to, from) in to.iter_mut().zip(from) {
        *to |= from;
    }
    out
}

/// `Ok` when `physical` has `VK_EXT_mesh_shader` with mesh stages,
/// `shaderDrawParameters` and the limits the mesh path's stages declare
/// (`shared::meshlet`); else what is missing.
/// Set (to anything), the renderer logs each compute pipeline's statistics as the
/// driver gives them (`VK_KHR_pipeline_executable_properties`: registers, shared
/// memory, instructions, spills), where the device has the extension.
pub const STATS_VARIABLE: &str = "GRASS_PIPELINE_STATS";

/// The device lists the extension `name`.
fn has_extension(instance: &ash::Instance, physical: vk::PhysicalDevice, name: &CStr) -> bool {
    let extensions =
        unsafe { instance.enumerate_device_extension_properties(physical) }.unwrap_or_default();
    extensions
        .iter()
        .any(|e| e.extension_name_as_c_str() == Ok(name))
}

fn mesh_shader_support(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
) -> Result<(), String> {
    use shared::draw::meshlet::{
        MESH_GRID_WIDTH, MESH_THREADS, MESHLET_TRIANGLES, MESHLET_VERTICES,
    };
    let name = ext::mesh_shader::NAME;
    if !has_extension(instance, physical, name) || feature_removed("meshShader") {
        return Err(format!("the device has no {}", name.to_string_lossy()));
    }
    let mut mesh = vk::PhysicalDeviceMeshShaderFeaturesEXT::default();
    let mut v11 = vk::PhysicalDeviceVulkan11Features::default();
    let mut features = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut mesh)
        .push_next(&mut v11);
    unsafe { instance.get_physical_device_features2(physical, &mut features) };
    if mesh.mesh_shader == vk::FALSE {
        return Err("VK_EXT_mesh_shader without mesh stages".into());
    }
    // The mesh stages tell their draws apart by `DrawIndex`.
    if v11.shader_draw_parameters == vk::FALSE {
        return Err("no shaderDrawParameters (the mesh stages read DrawIndex)".into());
    }
    let mut limits = vk::PhysicalDeviceMeshShaderPropertiesEXT::default();
    let mut props = vk::PhysicalDeviceProperties2::default().push_next(&mut limits);
    unsafe { instance.get_physical_device_properties2(physical, &mut props) };
    let needs = [
        (
            "maxMeshOutputVertices",
            limits.max_mesh_output_vertices,
            MESHLET_VERTICES,
        ),
        (
            "maxMeshOutputPrimitives",
            limits.max_mesh_output_primitives,
            MESHLET_TRIANGLES,
        ),
        (
            "maxMeshWorkGroupInvocations",
            limits.max_mesh_work_group_invocations,
            MESH_THREADS,
        ),
        (
            "maxMeshWorkGroupCount[0]",
            limits.max_mesh_work_group_count[0],
            MESH_GRID_WIDTH,
        ),
    ];
    match needs.iter().find(|(_, has, need)| has < need) {
        Some((limit, has, need)) => {
            Err(format!("mesh shader limit {limit} is {has}, {need} needed"))
        }
        None => Ok(()),
    }
}

/// `Ok` when `physical` has `shaderInt64` and `shaderBufferInt64Atomics` (the compute
/// rasterizer's visibility buffer, `shared::raster`); else what is missing. Fault
/// injection can take either away (`GRASS_FAULT=missing-feature:shaderBufferInt64Atomics`).
fn int64_atomics_support(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
) -> Result<(), String> {
    let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut v12);
    unsafe { instance.get_physical_device_features2(physical, &mut features) };
    let needs = [
        ("shaderInt64", features.features.shader_int64),
        ("shaderBufferInt64Atomics", v12.shader_buffer_int64_atomics),
    ];
    match needs
        .iter()
        .find(|(name, has)| *has == vk::FALSE || feature_removed(name))
    {
        Some((name, _)) => Err(format!("the device has no {name}")),
        None => Ok(()),
    }
}

/// `format`'s optimal-tiling features on `physical` contain `needed`.
pub fn format_has(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    format: vk::Format,
    needed: vk::FormatFeatureFlags,
) -> bool {
    let props = unsafe { instance.get_physical_device_format_properties(physical, format) };
    props.optimal_tiling_features.contains(needed)
}
