//! Who may connect: on 127.0.0.1 anyone (anonymous), as at the HMI; on another address only
//! the user with the password, at least 12 characters, and the server refuses to start on
//! one without it. A password given on 127.0.0.1 is required there too.

use async_trait::async_trait;
use opcua::crypto::SecurityPolicy;
use opcua::server::authenticator::{AuthManager, DefaultAuthenticator, Password, UserToken};
use opcua::server::{ServerBuilder, ServerEndpoint, ServerUserToken, ANONYMOUS_USER_TOKEN_ID};
use opcua::types::{Error, StatusCode, UserTokenPolicy, UserTokenType};
use std::collections::BTreeMap;
use std::net::SocketAddr;
use std::sync::Arc;

/// The port OPC UA servers listen on by convention (IANA: opcua-tcp).
pub const DEFAULT_PORT: u16 = 4840;
/// The user name clients log in with when none is given.
pub const DEFAULT_USER: &str = "operator";
/// The environment variable that gives the password when no argument does (it stays out of
/// the process list).
pub const PASSWORD_VARIABLE: &str = "SOFTNC_OPCUA_PASSWORD";
/// A password this short is refused (the HMI's token rule).
const MIN_PASSWORD: usize = 12;
/// The server's id of the one user token.
const USER_TOKEN_ID: &str = "softnc-user";
/// How clients encrypt the password on the endpoint without message security.
const PASSWORD_POLICY: SecurityPolicy = SecurityPolicy::Basic256Sha256;

/// Where the server listens and whom it takes.
#[derive(Clone)]
pub struct Access {
    pub addr: SocketAddr,
    /// User and password; `None`: anonymous clients (127.0.0.1 only).
    credential: Option<(String, String)>,
}

impl std::fmt::Debug for Access {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Access")
            .field("addr", &self.addr)
            .field("user", &self.credential.as_ref().map(|c| &c.0))
            .finish()
    }
}

impl Access {
    /// `listen`: `ADDRESS` or `ADDRESS:PORT` (default 127.0.0.1 and `port`); an address
    /// that is not loopback, the unspecified 0.0.0.0 and :: among them, needs the password
    /// (`password_flag` names the argument that gives it, for the message).
    pub fn new(
        listen: Option<&str>,
        port: u16,
        user: &str,
        password: Option<String>,
        password_flag: &str,
    ) -> Result<Access, String> {
        let addr = hmi_bridge::listen_address(listen, port)?;
        let password = password.filter(|p| !p.is_empty());
        if !addr.ip().is_loopback() && password.is_none() {
            return Err(format!(
                "listening on {addr} lets other machines read the control: give {password_flag} (or {PASSWORD_VARIABLE})"
            ));
        }
        if password
            .as_ref()
            .is_some_and(|p| p.chars().count() < MIN_PASSWORD)
        {
            return Err(format!(
                "the password is too short: use at least {MIN_PASSWORD} characters"
            ));
        }
        if password.is_some() && user.trim().is_empty() {
            return Err("the user name is empty".into());
        }
        Ok(Access {
            addr,
            credential: password.map(|p| (user.to_string(), p)),
        })
    }

    /// The endpoint (security policy None) and who may use it.
    pub fn configure(&self, builder: ServerBuilder) -> ServerBuilder {
        let builder = builder.discovery_urls(vec!["/".to_owned()]);
        match &self.credential {
            None => builder.add_endpoint(
                "none",
                ServerEndpoint::new_none("/", &[ANONYMOUS_USER_TOKEN_ID.to_string()]),
            ),
            Some((user, pass)) => {
                let token = ServerUserToken::user_pass(user.as_str(), pass.as_str());
                let users = BTreeMap::from([(USER_TOKEN_ID.to_string(), token.clone())]);
                let mut endpoint = ServerEndpoint::new_none("/", &[USER_TOKEN_ID.to_string()]);
                // The password is encrypted with the server's certificate (made at start).
                endpoint.password_security_policy = Some(PASSWORD_POLICY.to_str().to_string());
                builder
                    .create_sample_keypair(true)
                    .add_user_token(USER_TOKEN_ID, token)
                    .add_endpoint("none", endpoint)
                    .with_authenticator(Arc::new(Authenticator {
                        policies: DefaultAuthenticator::new(users),
                        user: user.clone(),
                        pass: pass.clone(),
                    }))
            }
        }
    }

    /// Who is taken, for the start-up line.
    pub fn describe(&self) -> String {
        match &self.credential {
            None => "(anonymous)".into(),
            Some((user, _)) => format!("(user '{user}' with password)"),
        }
    }
}

/// The one user, checked in constant time; the user token policies are the library's.
struct Authenticator {
    policies: DefaultAuthenticator,
    user: String,
    pass: String,
}

/// Equal in time that depends on the lengths only, not on where they differ.
fn same(a: &[u8], b: &[u8]) -> bool {
    let mut diff = u8::from(a.len() != b.len());
    for (x, y) in a.iter().zip(b) {
        diff |= x ^ y;
    }
    diff == 0
}

#[async_trait]
impl AuthManager for Authenticator {
    async fn authenticate_username_identity_token(
        &self,
        _endpoint: &ServerEndpoint,
        username: &str,
        password: &Password,
    ) -> Result<UserToken, Error> {
        let user_ok = same(username.as_bytes(), self.user.as_bytes());
        let pass_ok = same(password.get().as_bytes(), self.pass.as_bytes());
        if user_ok && pass_ok {
            Ok(UserToken(USER_TOKEN_ID.to_string()))
        } else {
            Err(Error::new(
                StatusCode::BadUserAccessDenied,
                "wrong user name or password",
            ))
        }
    }

    /// The library's policies, the password's marked to be encrypted with
    /// [`PASSWORD_POLICY`] (the library leaves its URI empty: clients would send it plain).
    fn user_token_policies(&self, endpoint: &ServerEndpoint) -> Vec<UserTokenPolicy> {
        let mut policies = self.policies.user_token_policies(endpoint);
        for p in &mut policies {
            if p.token_type == UserTokenType::UserName {
                p.security_policy_uri = PASSWORD_POLICY.to_uri().into();
            }
        }
        policies
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FLAG: &str = "--password";

    #[test]
    fn loopback_takes_anonymous_clients() {
        let a = Access::new(None, 4840, DEFAULT_USER, None, FLAG).unwrap();
        assert_eq!(a.addr, "127.0.0.1:4840".parse().unwrap());
        assert!(a.credential.is_none());
        let a = Access::new(Some("127.0.0.1:0"), 4840, DEFAULT_USER, None, FLAG).unwrap();
        assert_eq!(a.addr.port(), 0);
    }

    #[test]
    fn another_address_needs_a_long_password() {
        let e = Access::new(Some("0.0.0.0"), 4840, DEFAULT_USER, None, FLAG).unwrap_err();
        assert!(e.contains("--password (or SOFTNC_OPCUA_PASSWORD)"), "{e}");
        let e = Access::new(Some("0.0.0.0"), 4840, "op", Some(String::new()), FLAG).unwrap_err();
        assert!(e.contains("--password"), "{e}");
        let e = Access::new(Some("[::]:4841"), 1, "op", None, "--opcua-password").unwrap_err();
        assert!(
            e.contains("[::]:4841") && e.contains("--opcua-password"),
            "{e}"
        );
        let e =
            Access::new(Some("10.0.0.5:4841"), 1, "op", Some("short".into()), FLAG).unwrap_err();
        assert!(e.contains("at least 12"), "{e}");
        let long = || Some("long enough pw".to_string());
        let e = Access::new(Some("10.0.0.5"), 1, " ", long(), FLAG).unwrap_err();
        assert!(e.contains("user"), "{e}");
        let a = Access::new(Some("10.0.0.5"), 4841, "op", long(), FLAG).unwrap();
        assert_eq!(a.addr, "10.0.0.5:4841".parse().unwrap());
        assert_eq!(a.describe(), "(user 'op' with password)");
        let a = Access::new(Some("0.0.0.0"), 0, "op", long(), FLAG).unwrap();
        assert!(a.credential.is_some());
        assert!(Access::new(Some("nowhere"), 1, "op", None, FLAG).is_err());
    }

    /// IPv6 loopback is loopback: anonymous clients there as on 127.0.0.1.
    #[test]
    fn ipv6_loopback_takes_anonymous_clients() {
        let a = Access::new(Some("::1"), 4840, DEFAULT_USER, None, FLAG).unwrap();
        assert_eq!(a.addr, "[::1]:4840".parse().unwrap());
        assert_eq!(a.describe(), "(anonymous)");
    }

    /// On another address the password is to be encrypted with Basic256Sha256 (the
    /// server's certificate); no anonymous policy is offered.
    #[test]
    fn the_password_policy_asks_for_encryption() {
        let token = ServerUserToken::user_pass("op", "long enough pw");
        let users = BTreeMap::from([(USER_TOKEN_ID.to_string(), token)]);
        let auth = Authenticator {
            policies: DefaultAuthenticator::new(users),
            user: "op".into(),
            pass: "long enough pw".into(),
        };
        let mut endpoint = ServerEndpoint::new_none("/", &[USER_TOKEN_ID.to_string()]);
        endpoint.password_security_policy = Some(PASSWORD_POLICY.to_str().to_string());
        let policies = auth.user_token_policies(&endpoint);
        assert_eq!(policies.len(), 1, "{policies:?}");
        assert_eq!(policies[0].token_type, UserTokenType::UserName);
        assert_eq!(
            policies[0].security_policy_uri.as_ref(),
            "http://opcfoundation.org/UA/SecurityPolicy#Basic256Sha256"
        );
    }

    #[test]
    fn comparison() {
        assert!(same(b"abcdefghijkl", b"abcdefghijkl"));
        assert!(!same(b"abcdefghijkl", b"abcdefghijkm"));
        assert!(!same(b"abcdefghijkl", b"abcdefghijk"));
        assert!(!same(b"", b"a"));
        assert!(same(b"", b""));
    }
}
