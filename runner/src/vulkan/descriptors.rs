//! A descriptor set layout, its pool and its one set.

use super::Context;
use anyhow::{Context as _, Result};
use ash::vk;
use std::sync::Arc;

/// One binding of a set, as the runner declares it (a test compares these with the
/// bindings the compiled shaders declare).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct BindingSpec {
    /// Binding number.
    pub binding: u32,
    /// Descriptor type.
    pub ty: vk::DescriptorType,
    /// Stages that see it.
    pub stages: vk::ShaderStageFlags,
}

/// A set layout with one set allocated from its own pool.
pub struct DescriptorSet {
    ctx: Arc<Context>,
    /// The layout.
    pub layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    /// The set.
    pub set: vk::DescriptorSet,
}

impl DescriptorSet {
    /// Layout, pool and set for `bindings`.
    pub fn new(ctx: &Arc<Context>, bindings: &[BindingSpec]) -> Result<Self> {
        let device = &ctx.device;
        let layout_bindings: Vec<_> = bindings
            .iter()
            .map(|b| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(b.binding)
                    .descriptor_type(b.ty)
                    .descriptor_count(1)
                    .stage_flags(b.stages)
            })
            .collect();
        let layout = unsafe {
            device.create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings),
                None,
            )
        }
        .context("create descriptor set layout")?;
        let sizes: Vec<_> = bindings
            .iter()
            .map(|b| vk::DescriptorPoolSize {
                ty: b.ty,
                descriptor_count: 1,
            })
            .collect();
        let pool = unsafe {
            device.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(1)
                    .pool_sizes(&sizes),
                None,
            )
        }
        .context("create descriptor pool")?;
        let layouts = [layout];
        let set = unsafe {
            device.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(pool)
                    .set_layouts(&layouts),
            )
        }
        .context("allocate descriptor set")?[0];
        Ok(Self {
            ctx: ctx.clone(),
            layout,
            pool,
            set,
        })
    }

    /// Points `binding` (of type `ty`) at the whole of `buffer`.
    pub fn write_buffer(&self, binding: u32, ty: vk::DescriptorType, buffer: vk::Buffer) {
        let info = [vk::DescriptorBufferInfo {
            buffer,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(binding)
            .descriptor_type(ty)
            .buffer_info(&info);
        unsafe { self.ctx.device.update_descriptor_sets(&[write], &[]) };
    }
}

impl DescriptorSet {
    /// Points `binding` (a combined image sampler) at `view`, in
    /// SHADER_READ_ONLY_OPTIMAL, sampled through `sampler`.
    pub fn write_image(&self, binding: u32, view: vk::ImageView, sampler: vk::Sampler) {
        let ty = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        self.write_image_info(binding, ty, view, sampler);
    }

    /// Points `binding` (a sampled image) at `view`, in SHADER_READ_ONLY_OPTIMAL.
    pub fn write_sampled_image(&self, binding: u32, view: vk::ImageView) {
        let ty = vk::DescriptorType::SAMPLED_IMAGE;
        self.write_image_info(binding, ty, view, vk::Sampler::null());
    }

    /// Points `binding` (a storage image) at `view`, in GENERAL.
    pub fn write_storage_image(&self, binding: u32, view: vk::ImageView) {
        let info = [vk::DescriptorImageInfo {
            sampler: vk::Sampler::null(),
            image_view: view,
            image_layout: vk::ImageLayout::GENERAL,
        }];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(binding)
            .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
            .image_info(&info);
        unsafe { self.ctx.device.update_descriptor_sets(&[write], &[]) };
    }

    /// Points `binding` (a sampler) at `sampler`.
    pub fn write_sampler(&self, binding: u32, sampler: vk::Sampler) {
        let ty = vk::DescriptorType::SAMPLER;
        self.write_image_info(binding, ty, vk::ImageView::null(), sampler);
    }

    /// One image descriptor of type `ty`: `view` (if any) in SHADER_READ_ONLY_OPTIMAL
    /// and `sampler` (if any).
    fn write_image_info(
        &self,
        binding: u32,
        ty: vk::DescriptorType,
        view: vk::ImageView,
        sampler: vk::Sampler,
    ) {
        let info = [vk::DescriptorImageInfo {
            sampler,
            image_view: view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        }];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(binding)
            .descriptor_type(ty)
            .image_info(&info);
        unsafe { self.ctx.device.update_descriptor_sets(&[write], &[]) };
    }
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        unsafe {
            self.ctx.device.destroy_descriptor_pool(self.pool, None);
            self.ctx
                .device
                .destroy_descriptor_set_layout(self.layout, None);
        }
    }
}
