//! `underlight devices`: the Vulkan devices and whether each has what underlight needs.

use anyhow::{bail, Result};

pub(super) fn run() -> Result<i32> {
    let instance = underlight::vk::instance::Instance::new(false, &[])?;
    let devices = underlight::vk::device::enumerate(&instance)?;
    if devices.is_empty() {
        bail!(underlight::Error::NoDevice);
    }
    for d in &devices {
        let missing = underlight::vk::features::missing_features(&d.capabilities);
        let verdict = if missing.is_empty() { "suitable".to_string() } else { format!("lacks {}", missing.join(", ")) };
        println!("{}: {verdict}", d.describe());
    }
    Ok(0)
}
