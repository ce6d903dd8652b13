//! The OPC UA server inside the HMI bridge's process (`softnc hmi-bridge --opcua`): a guest
//! on the bridge's link (hmi_bridge::Guest), so the control has one reader of the kernel
//! instead of two. The server keeps its own thread and async runtime; the bridge's HTTP
//! workers and its link thread never wait on it. Its rules are `softnc opcua`'s.

use crate::{identity, start, ServerOptions};
use hmi_bridge::BridgeArgs;
use nc_runtime::Failure;

/// hmi-bridge, with the OPC UA server in it when `options` ask for one. The server's
/// arguments are checked before the bridge starts; a server that cannot listen keeps the
/// bridge from starting, and one that fails later ends it.
pub fn bridge_main(bridge: BridgeArgs, options: ServerOptions) -> Result<(), Failure> {
    let guest: Option<hmi_bridge::Guest> = match options.access()? {
        None => None,
        Some(access) => {
            let identity = identity(&bridge.control)?;
            Some(Box::new(move |link, stop| {
                start(access, identity, link, stop).map(|running| running.thread)
            }))
        }
    };
    hmi_bridge::main_with(bridge, guest)
}
