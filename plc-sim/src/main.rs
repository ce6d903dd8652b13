//! plc-sim: a process of the softnc control. Its cyclic function is built in a later issue; until
//! then it only reports that and exits with status 2, so that nothing mistakes it for a peer.

fn main() {
    eprintln!(
        "plc-sim: not built yet (services under the prefix '{}' are defined in a later issue)",
        softnc_protocol::DEFAULT_INSTANCE
    );
    std::process::exit(2);
}
