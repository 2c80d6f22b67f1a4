//! GPU timestamp queries per pass.

/// Reading timestamps back failed (the device was lost or mapping failed).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("reading GPU timestamps failed: {0}")]
pub struct TimestampError(pub String);

/// Maps `slice` for reading and waits until it is mapped. A browser's WebGPU maps
/// buffers only between the page's tasks, never while the caller waits: there the
/// wait fails with an error instead of blocking for ever.
pub(crate) fn map_blocking(
    device: &wgpu::Device,
    slice: &wgpu::BufferSlice<'_>,
) -> Result<(), String> {
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| e.to_string())?;
    let mapped = if cfg!(target_arch = "wasm32") {
        rx.try_recv().map_err(|_| {
            "a blocking GPU readback is unavailable on the web (WebGPU maps buffers only \
             between the page's tasks)"
                .to_string()
        })?
    } else {
        rx.recv().map_err(|e| e.to_string())?
    };
    mapped.map_err(|e| e.to_string())
}

/// GPU timestamp queries in begin/end pairs, one pair per timed pass, with their
/// resolve and readback buffers (needs `Features::TIMESTAMP_QUERY`).
#[derive(Debug)]
pub struct TimestampPairs {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    pairs: u32,
}

impl TimestampPairs {
    /// Queries for `pairs` timed passes.
    pub fn new(device: &wgpu::Device, label: &str, pairs: u32) -> Self {
        let size = u64::from(pairs) * 16;
        let buffer = |suffix: &str, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&format!("{label} {suffix}")),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        Self {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some(label),
                ty: wgpu::QueryType::Timestamp,
                count: pairs * 2,
            }),
            resolve: buffer(
                "resolve",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: buffer(
                "readback",
                wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            ),
            pairs,
        }
    }

    /// Timestamp writes of a compute pass timed as pair `pair`.
    pub fn compute(&self, pair: u32) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(pair * 2),
            end_of_pass_write_index: Some(pair * 2 + 1),
        }
    }

    /// Timestamp writes of a render pass timed as (part of) pair `pair`: `begin` and
    /// `end` choose which ends this pass writes, so consecutive passes can share a pair.
    pub fn render(&self, pair: u32, begin: bool, end: bool) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: begin.then_some(pair * 2),
            end_of_pass_write_index: end.then_some(pair * 2 + 1),
        }
    }

    /// Resolves every pair into the readback buffer; record before submitting.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..self.pairs * 2, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, self.resolve.size());
    }

    /// Milliseconds of every pair of the last resolved submission (blocks until the
    /// GPU is done); a pair whose end is not after its begin reads 0.
    pub fn read_ms(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Vec<f64>, TimestampError> {
        let period_ns = f64::from(queue.get_timestamp_period());
        let slice = self.readback.slice(..);
        map_blocking(device, &slice).map_err(TimestampError)?;
        let ticks: Vec<u64> = {
            let data = slice
                .get_mapped_range()
                .map_err(|e| TimestampError(e.to_string()))?;
            bytemuck::cast_slice::<u8, u64>(&data).to_vec()
        };
        self.readback.unmap();
        Ok(ticks
            .chunks_exact(2)
            .map(|p| {
                if p[1] > p[0] {
                    (p[1] - p[0]) as f64 * period_ns / 1.0e6
                } else {
                    0.0
                }
            })
            .collect())
    }

    /// Bytes of the resolve and readback buffers.
    pub fn buffer_bytes(&self) -> u64 {
        self.resolve.size() + self.readback.size()
    }
}
