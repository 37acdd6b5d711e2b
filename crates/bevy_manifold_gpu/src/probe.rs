//! Whether there is a GPU adapter, without opening a device.

use crate::GpuError;

/// The default GPU adapter's name, backend and driver, without opening a
/// device: whether the GPU tracer and Bevy's renderer can run here.
///
/// # Errors
/// [`GpuError::NoAdapter`] when there is none.
pub fn probe_adapter() -> Result<String, GpuError> {
    let info = probe_adapter_info()?;
    Ok(format!("{} ({:?}, {})", info.name, info.backend, info.driver_info))
}

/// [`probe_adapter`]'s adapter, in wgpu's terms (its device type says
/// whether it is a software rasteriser).
///
/// # Errors
/// [`GpuError::NoAdapter`] when there is none.
pub fn probe_adapter_info() -> Result<wgpu::AdapterInfo, GpuError> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
    }))
    .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
    Ok(adapter.get_info())
}
