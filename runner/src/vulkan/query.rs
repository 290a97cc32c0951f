//! Query pools: GPU time between points of a frame (timestamps), and the triangles a
//! draw generates (pipeline statistics).

use super::Context;
use anyhow::{Context as _, Result};
use ash::vk;
use std::sync::Arc;

/// A pool of `count` timestamps, read after the frame that wrote them has finished.
pub struct TimestampPool {
    ctx: Arc<Context>,
    /// The pool.
    pub pool: vk::QueryPool,
    /// Number of timestamps.
    pub count: u32,
}

impl TimestampPool {
    /// A pool of `count` timestamps, or `None` when the queue has no timestamps.
    pub fn new(ctx: &Arc<Context>, count: u32) -> Result<Option<Self>> {
        if ctx.timestamp_bits == 0 || ctx.properties.limits.timestamp_period <= 0.0 {
            return Ok(None);
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(count);
        let pool = unsafe { ctx.device.create_query_pool(&info, None) }
            .context("create timestamp query pool")?;
        Ok(Some(Self {
            ctx: ctx.clone(),
            pool,
            count,
        }))
    }

    /// Milliseconds from the first timestamp to each timestamp (0 for the first), when
    /// all are available.
    pub fn read_all_ms(&self) -> Option<Vec<f64>> {
        let rest = self.read_ms()?;
        Some(std::iter::once(0.0).chain(rest).collect())
    }

    /// Milliseconds from the first timestamp to each of the others, when all are
    /// available (no waiting: call once the frame's fence has signalled).
    pub fn read_ms(&self) -> Option<Vec<f64>> {
        let mut ticks = vec![0u64; self.count as usize];
        unsafe {
            self.ctx.device.get_query_pool_results(
                self.pool,
                0,
                &mut ticks,
                vk::QueryResultFlags::TYPE_64,
            )
        }
        .ok()?;
        let bits = self.ctx.timestamp_bits;
        let mask = if bits >= 64 {
            u64::MAX
        } else {
            (1u64 << bits) - 1
        };
        let period_ns = f64::from(self.ctx.properties.limits.timestamp_period);
        let start = ticks[0] & mask;
        Some(
            ticks[1..]
                .iter()
                .map(|t| ((t & mask).wrapping_sub(start) & mask) as f64 * period_ns * 1e-6)
                .collect(),
        )
    }
}

impl Drop for TimestampPool {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_query_pool(self.pool, None) };
    }
}

/// One pipeline-statistics query counting the primitives that reach the clipper: the
/// triangles a draw generates after tessellation.
pub struct TrianglePool {
    ctx: Arc<Context>,
    /// The pool.
    pub pool: vk::QueryPool,
}

impl TrianglePool {
    /// The query, or `None` when the device has no pipeline statistics.
    pub fn new(ctx: &Arc<Context>) -> Result<Option<Self>> {
        if !ctx.pipeline_statistics {
            return Ok(None);
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .query_count(1)
            .pipeline_statistics(vk::QueryPipelineStatisticFlags::CLIPPING_INVOCATIONS);
        let pool = unsafe { ctx.device.create_query_pool(&info, None) }
            .context("create pipeline statistics query pool")?;
        Ok(Some(Self {
            ctx: ctx.clone(),
            pool,
        }))
    }

    /// The triangles counted, when available (no waiting: call once the frame's fence
    /// has signalled).
    pub fn read(&self) -> Option<u64> {
        let mut count = [0u64];
        unsafe {
            self.ctx.device.get_query_pool_results(
                self.pool,
                0,
                &mut count,
                vk::QueryResultFlags::TYPE_64,
            )
        }
        .ok()?;
        Some(count[0])
    }
}

impl Drop for TrianglePool {
    fn drop(&mut self) {
        unsafe { self.ctx.device.destroy_query_pool(self.pool, None) };
    }
}
