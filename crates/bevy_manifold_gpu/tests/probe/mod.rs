//! Runs one WGSL function of the tracer on the device: a small compute
//! shader (a probe) composed with the tracer's modules, its inputs in
//! read-only storage buffers, its output read back. For the GPU twins of
//! CPU functions that no image comparison pins down (the tests that
//! `mod probe;` this file).

use bevy_manifold_gpu::{GpuTracer, SHADER_IMPORTS, WgslModule};

/// Runs `entry` of `probe` (composed with `defs`) over `invocations`
/// (workgroups of 64), with `inputs` bound read-only at their binding
/// numbers and an output of `output_bytes` read-write at `output`; returns
/// the output's bytes.
pub fn run(
    probe: WgslModule,
    defs: &[&'static str],
    entry: &str,
    inputs: &[(u32, &[u8])],
    (output, output_bytes): (u32, u64),
    invocations: u32,
) -> Vec<u8> {
    use wgpu::util::DeviceExt;
    let module = GpuTracer::compose_modules(&SHADER_IMPORTS, probe, defs, &[]).expect("the probe composes");
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter =
        pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default())).expect("an adapter");
    let (device, queue) =
        pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor::default())).expect("a device");
    let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(probe.path),
        source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(probe.path),
        layout: None,
        module: &shader,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    });
    let buffers: Vec<(u32, wgpu::Buffer)> = inputs
        .iter()
        .map(|&(binding, bytes)| {
            let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("probe input"),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            });
            (binding, buffer)
        })
        .collect();
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe output"),
        size: output_bytes,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe readback"),
        size: output_bytes,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut entries: Vec<wgpu::BindGroupEntry> = buffers
        .iter()
        .map(|(binding, buffer)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: buffer.as_entire_binding(),
        })
        .collect();
    entries.push(wgpu::BindGroupEntry {
        binding: output,
        resource: out.as_entire_binding(),
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(probe.path),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups(invocations.div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&out, 0, &readback, 0, output_bytes);
    queue.submit([encoder.finish()]);
    readback.map_async(wgpu::MapMode::Read, .., |r| r.expect("the output maps"));
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("the device finishes");
    readback.get_mapped_range(..).to_vec()
}
