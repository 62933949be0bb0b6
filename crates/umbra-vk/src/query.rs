//! Query pools: timestamps, occlusion and pipeline statistics.

use crate::error::{CallContext, VkError, VkResult};
use crate::Context;
use ash::vk;

/// What a query pool counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QueryKind {
    /// GPU timestamps (ticks of `Capabilities::timestamp_period_ns`).
    Timestamp,
    /// Samples that passed the depth and stencil tests.
    Occlusion,
    /// Fragment-shader invocations (needs `pipelineStatisticsQuery`).
    FragmentInvocations,
}

/// How long [`QueryPool::first_results`] waits for results of completed commands.
pub const QUERY_WAIT: std::time::Duration = std::time::Duration::from_secs(10);

/// A query pool; destroyed on drop.
pub struct QueryPool {
    /// The raw pool.
    pub raw: vk::QueryPool,
    /// What it counts.
    pub kind: QueryKind,
    /// Number of queries.
    pub count: u32,
    ctx: Context,
}

impl QueryPool {
    /// Creates a pool of `count` queries; `Unsupported` when the device cannot count `kind`.
    pub fn new(ctx: &Context, name: &str, kind: QueryKind, count: u32) -> VkResult<Self> {
        let caps = ctx.capabilities();
        if count == 0 {
            return Err(VkError::InvalidDesc { what: "query pool", why: format!("{name}: zero queries") });
        }
        let mut info = vk::QueryPoolCreateInfo::default().query_count(count);
        info = match kind {
            QueryKind::Timestamp if !caps.timestamps => return Err(ctx.unsupported("timestamp queries")),
            QueryKind::FragmentInvocations if !caps.pipeline_statistics => {
                return Err(ctx.unsupported("pipeline statistics queries (pipelineStatisticsQuery)"))
            }
            QueryKind::Timestamp => info.query_type(vk::QueryType::TIMESTAMP),
            QueryKind::Occlusion => info.query_type(vk::QueryType::OCCLUSION),
            QueryKind::FragmentInvocations => info
                .query_type(vk::QueryType::PIPELINE_STATISTICS)
                .pipeline_statistics(vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS),
        };
        // SAFETY: valid create info; features checked above; destroyed in `Drop`.
        let raw = unsafe { ctx.inner.device.create_query_pool(&info, None) }.call("vkCreateQueryPool")?;
        ctx.set_name(raw, name);
        Ok(Self { raw, kind, count, ctx: ctx.clone() })
    }

    /// Every query's 64-bit result, waiting for them to be available.
    pub fn results(&self) -> VkResult<Vec<u64>> {
        self.first_results(self.count)
    }

    /// The results of the first `count` queries (those a recording wrote), waiting for them.
    ///
    /// Call it once the commands that wrote them completed. It polls rather than passing
    /// `VK_QUERY_RESULT_WAIT_BIT`, whose wait has no timeout (a query reset but never written
    /// would hang the caller): results still missing after [`QUERY_WAIT`] are `VK_TIMEOUT`.
    pub fn first_results(&self, count: u32) -> VkResult<Vec<u64>> {
        let start = std::time::Instant::now();
        loop {
            if let Some(results) = self.available_results(count)? {
                return Ok(results);
            }
            if start.elapsed() > QUERY_WAIT {
                return Err(vk::Result::TIMEOUT).call("vkGetQueryPoolResults (results never became available)");
            }
            std::thread::yield_now();
        }
    }

    /// The results of the first `count` queries when the GPU has written them all, `None` while
    /// it has not: never waits (for results of an engine's earlier frame).
    pub fn available_results(&self, count: u32) -> VkResult<Option<Vec<u64>>> {
        if count == 0 || count > self.count {
            return Err(VkError::InvalidDesc {
                what: "query results",
                why: format!("{count} of a pool of {} queries", self.count),
            });
        }
        let mut data = vec![0u64; count as usize];
        // SAFETY: `data` holds one u64 per query (each kind here yields one value).
        let result = unsafe {
            self.ctx.inner.device.get_query_pool_results(self.raw, 0, &mut data, vk::QueryResultFlags::TYPE_64)
        };
        match result {
            Ok(()) => Ok(Some(data)),
            Err(vk::Result::NOT_READY) => Ok(None),
            Err(e) => Err(e).call("vkGetQueryPoolResults"),
        }
    }

    /// Nanoseconds between two timestamps of this pool's results, honouring the valid bits.
    pub fn elapsed_ns(&self, results: &[u64], begin: usize, end: usize) -> f64 {
        let caps = self.ctx.capabilities();
        let mask = if caps.timestamp_valid_bits >= 64 { u64::MAX } else { (1u64 << caps.timestamp_valid_bits) - 1 };
        let (Some(&b), Some(&e)) = (results.get(begin), results.get(end)) else {
            return 0.0;
        };
        (e.wrapping_sub(b) & mask) as f64 * caps.timestamp_period_ns as f64
    }
}

impl Drop for QueryPool {
    fn drop(&mut self) {
        // SAFETY: umbra waits for every submission, so the pool is no longer in use.
        unsafe { self.ctx.inner.device.destroy_query_pool(self.raw, None) };
    }
}
