//! softnc-protocol: payload types and service names shared by nc-kernel, plc-sim and
//! hmi-bridge. The iceoryx2 services are defined in the IPC issue; this crate pins the
//! naming scheme now so that every process agrees on it from the start.

/// Default instance prefix for service names; tests and side-by-side machines set their own.
pub const DEFAULT_INSTANCE: &str = "softnc";

/// The full service name for `service` under `instance` (`softnc/setpoints`).
pub fn service_name(instance: &str, service: &str) -> String {
    format!("{instance}/{service}")
}

#[cfg(test)]
mod tests {
    #[test]
    fn names_are_prefixed() {
        assert_eq!(super::service_name("a", "setpoints"), "a/setpoints");
    }
}
