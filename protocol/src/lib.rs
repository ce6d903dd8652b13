//! softnc-protocol: what nc-kernel, plc-sim, hmi-bridge and the `softnc` command exchange,
//! and how they open the services. The one iceoryx2 version of all of them is this crate's
//! (re-exported), so no two processes can be built against different ones.

pub mod layout;
pub mod payload;
pub mod services;

pub use iceoryx2;
pub use payload::*;
pub use services::{
    abi, newest, receive_each, Instance, IpcError, Released, Sub, User, DEFAULT_INSTANCE, ROLES,
};
