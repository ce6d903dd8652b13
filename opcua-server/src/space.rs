//! The address space: `Objects/Machines/<name>` with the OPC 40501-1 subset softnc fills,
//! built once from the standard types (FolderType, BaseObjectType, BaseDataVariableType,
//! PropertyType) and written from [`Values`] while the server runs. The companion
//! specification's browse names are in its namespace, softnc's additions in its own; every
//! node id is a string in softnc's namespace (docs/opcua.md has the tree).

use crate::model::{self, Values};
use opcua::nodes::{NodeSetImport, NodeSetNamespaceMapper};
use opcua::server::address_space::{AddressSpace, ImportedItem, ObjectBuilder, VariableBuilder};
use opcua::server::node_manager::memory::SimpleNodeManager;
use opcua::server::SubscriptionCache;
use opcua::types::{
    DataTypeId, DataValue, DateTime, LocalizedText, NodeId, ObjectId, ObjectTypeId, QualifiedName,
    StatusCode, VariableTypeId, Variant,
};
use softnc_protocol::ToolTableMsg;
use std::sync::Arc;

/// OPC 40501-1's namespace: the browse names the companion specification defines.
pub const MACHINE_TOOL_NS: &str = "http://opcfoundation.org/UA/MachineTool/";
/// softnc's own: its node ids and the variables the specification does not have.
pub const SOFTNC_NS: &str = "urn:softnc:UA";

/// Registers both namespaces with the server; no nodes come from it (they are built here).
pub struct Namespaces;

impl NodeSetImport for Namespaces {
    fn register_namespaces(&self, namespaces: &mut NodeSetNamespaceMapper) {
        namespaces.add_namespace(MACHINE_TOOL_NS, 1);
        namespaces.add_namespace(SOFTNC_NS, 2);
    }

    fn get_own_namespaces(&self) -> Vec<String> {
        vec![MACHINE_TOOL_NS.to_string(), SOFTNC_NS.to_string()]
    }

    fn load<'a>(
        &'a self,
        _namespaces: &'a NodeSetNamespaceMapper,
    ) -> Box<dyn Iterator<Item = ImportedItem> + 'a> {
        Box::new(std::iter::empty())
    }
}

/// Which namespace a browse name is in.
#[derive(Clone, Copy)]
enum Ns {
    MachineTool,
    Softnc,
}

/// What Identification says.
pub struct Identity {
    pub model: String,
    pub serial: String,
}

/// The machine's nodes and the server's handles to write them.
pub struct Space {
    manager: Arc<SimpleNodeManager>,
    subscriptions: Arc<SubscriptionCache>,
    mt: u16,
    own: u16,
    /// The machine's name: the first part of every node id.
    root: String,
    /// The tool table's version the Tools folder shows, and its entries' nodes.
    tools_version: Option<u32>,
    tool_nodes: Vec<NodeId>,
}

/// A variable: its path under the machine, its namespace, data type and array-ness.
struct Var(&'static str, Ns, DataTypeId, bool);

/// The variables written every update, in the order [`Space::values`] gives them.
const VARIABLES: &[Var] = &[
    Var(
        "Monitoring/Channel_1/ChannelState",
        Ns::MachineTool,
        DataTypeId::Int32,
        false,
    ),
    Var(
        "Monitoring/Channel_1/ChannelMode",
        Ns::MachineTool,
        DataTypeId::Int32,
        false,
    ),
    Var(
        "Monitoring/Channel_1/FeedOverride",
        Ns::MachineTool,
        DataTypeId::Double,
        false,
    ),
    Var(
        "Monitoring/Channel_1/FeedRate",
        Ns::Softnc,
        DataTypeId::Double,
        false,
    ),
    Var(
        "Monitoring/Channel_1/ProgramName",
        Ns::Softnc,
        DataTypeId::String,
        false,
    ),
    Var(
        "Monitoring/Channel_1/ProgramPath",
        Ns::Softnc,
        DataTypeId::String,
        false,
    ),
    Var(
        "Monitoring/Channel_1/Line",
        Ns::Softnc,
        DataTypeId::UInt32,
        false,
    ),
    Var(
        "Monitoring/Channel_1/Block",
        Ns::Softnc,
        DataTypeId::String,
        false,
    ),
    Var(
        "Monitoring/Channel_1/Tool",
        Ns::Softnc,
        DataTypeId::UInt32,
        false,
    ),
    Var(
        "Monitoring/Channel_1/Edge",
        Ns::Softnc,
        DataTypeId::UInt32,
        false,
    ),
    Var(
        "Monitoring/Channel_1/KernelConnected",
        Ns::Softnc,
        DataTypeId::Boolean,
        false,
    ),
    Var(
        "Monitoring/Spindle_1/IsRotating",
        Ns::MachineTool,
        DataTypeId::Boolean,
        false,
    ),
    Var(
        "Monitoring/Spindle_1/SpeedSetpoint",
        Ns::Softnc,
        DataTypeId::Double,
        false,
    ),
    Var(
        "Monitoring/Spindle_1/SpeedActual",
        Ns::Softnc,
        DataTypeId::Double,
        false,
    ),
    Var(
        "Production/ActiveProgram/Name",
        Ns::MachineTool,
        DataTypeId::String,
        false,
    ),
    Var(
        "Production/ActiveProgram/State/CurrentState",
        Ns::MachineTool,
        DataTypeId::LocalizedText,
        false,
    ),
    Var(
        "Notification/Alarms/AlarmCount",
        Ns::Softnc,
        DataTypeId::UInt32,
        false,
    ),
    Var(
        "Notification/Alarms/Numbers",
        Ns::Softnc,
        DataTypeId::UInt32,
        true,
    ),
    Var(
        "Notification/Alarms/Texts",
        Ns::Softnc,
        DataTypeId::String,
        true,
    ),
    Var(
        "Notification/Alarms/Programs",
        Ns::Softnc,
        DataTypeId::String,
        true,
    ),
    Var(
        "Notification/Alarms/Lines",
        Ns::Softnc,
        DataTypeId::UInt32,
        true,
    ),
];

/// The objects, parent before child: path, namespace, folder (FolderType) or not.
const OBJECTS: &[(&str, Ns, bool)] = &[
    ("Identification", Ns::MachineTool, false),
    ("Monitoring", Ns::MachineTool, false),
    ("Monitoring/MachineTool", Ns::MachineTool, false),
    ("Monitoring/Channel_1", Ns::MachineTool, false),
    ("Monitoring/Spindle_1", Ns::MachineTool, false),
    ("Production", Ns::MachineTool, false),
    ("Production/ActiveProgram", Ns::MachineTool, false),
    ("Production/ActiveProgram/State", Ns::MachineTool, false),
    ("Notification", Ns::MachineTool, false),
    ("Notification/Alarms", Ns::Softnc, false),
    ("Equipment", Ns::MachineTool, false),
    ("Equipment/Tools", Ns::MachineTool, true),
];

impl Space {
    /// Builds the machine's nodes under Objects/Machines.
    pub fn new(
        manager: Arc<SimpleNodeManager>,
        subscriptions: Arc<SubscriptionCache>,
        name: &str,
        identity: &Identity,
    ) -> Result<Space, String> {
        let (mt, own) = {
            let space = manager.address_space().read();
            let index = |uri: &str| {
                space
                    .namespace_index(uri)
                    .ok_or_else(|| format!("namespace {uri} is not registered"))
            };
            (index(MACHINE_TOOL_NS)?, index(SOFTNC_NS)?)
        };
        let s = Space {
            manager,
            subscriptions,
            mt,
            own,
            root: name.to_string(),
            tools_version: None,
            tool_nodes: Vec::new(),
        };
        s.build(identity);
        Ok(s)
    }

    fn id(&self, path: &str) -> NodeId {
        if path.is_empty() {
            NodeId::new(self.own, self.root.clone())
        } else {
            NodeId::new(self.own, format!("{}/{path}", self.root))
        }
    }

    fn name(&self, ns: Ns, name: &str) -> QualifiedName {
        let index = match ns {
            Ns::MachineTool => self.mt,
            Ns::Softnc => self.own,
        };
        QualifiedName::new(index, name)
    }

    /// The parent's id and the last part of a path.
    fn split<'p>(&self, path: &'p str) -> (NodeId, &'p str) {
        match path.rsplit_once('/') {
            Some((parent, last)) => (self.id(parent), last),
            None => (self.id(""), path),
        }
    }

    fn build(&self, identity: &Identity) {
        let mut space = self.manager.address_space().write();
        let machines = NodeId::new(self.own, "Machines");
        ObjectBuilder::new(
            &machines,
            self.name(Ns::MachineTool, "Machines"),
            "Machines",
        )
        .is_folder()
        .organized_by(ObjectId::ObjectsFolder)
        .insert(&mut *space);
        ObjectBuilder::new(
            &self.id(""),
            self.name(Ns::Softnc, &self.root),
            self.root.as_str(),
        )
        .has_type_definition(ObjectTypeId::BaseObjectType)
        .organized_by(machines)
        .insert(&mut *space);
        for &(path, ns, folder) in OBJECTS {
            let (parent, last) = self.split(path);
            let b = ObjectBuilder::new(&self.id(path), self.name(ns, last), last);
            let b = if folder {
                b.is_folder()
            } else {
                b.has_type_definition(ObjectTypeId::BaseObjectType)
            };
            b.component_of(parent).insert(&mut *space);
        }
        self.fixed_values(&mut space, identity);
        for v in VARIABLES {
            let (parent, last) = self.split(v.0);
            let b = VariableBuilder::new(&self.id(v.0), self.name(v.1, last), last)
                .data_type(v.2)
                .has_type_definition(VariableTypeId::BaseDataVariableType)
                .component_of(parent);
            let b = if v.3 {
                b.value_rank(1)
            } else {
                b.value_rank(-1)
            };
            b.insert(&mut *space);
        }
    }

    /// Identification's properties (OPC 40501-1 8.2: MachineToolIdentificationType), the
    /// monitored elements' names (8.3.2 ElementMonitoringType) and the machine's operation
    /// mode (8.3.3: Automatic, 1, the only one softnc has).
    fn fixed_values(&self, space: &mut AddressSpace, identity: &Identity) {
        let revision = env!("CARGO_PKG_VERSION");
        let uri = format!("urn:softnc:{}", identity.serial);
        let properties: [(&str, Variant); 7] = [
            (
                "Identification/Manufacturer",
                LocalizedText::new("", "softnc").into(),
            ),
            (
                "Identification/Model",
                LocalizedText::new("", &identity.model).into(),
            ),
            (
                "Identification/SerialNumber",
                identity.serial.as_str().into(),
            ),
            ("Identification/SoftwareRevision", revision.into()),
            ("Identification/ProductInstanceUri", uri.as_str().into()),
            ("Monitoring/Channel_1/Name", "Channel 1".into()),
            ("Monitoring/Spindle_1/Name", "Spindle 1".into()),
        ];
        for (path, value) in properties {
            self.fixed(space, path, Ns::MachineTool, value, true);
        }
        let mode = "Monitoring/MachineTool/OperationMode";
        self.fixed(space, mode, Ns::MachineTool, Variant::Int32(1), false);
        let version = "Equipment/Tools/TableVersion";
        self.fixed(space, version, Ns::Softnc, Variant::UInt32(0), true);
    }

    /// A variable with its value at `path`: a property of its parent or a component.
    fn fixed(&self, space: &mut AddressSpace, path: &str, ns: Ns, value: Variant, property: bool) {
        let (parent, last) = self.split(path);
        let data_type = match value {
            Variant::LocalizedText(_) => DataTypeId::LocalizedText,
            Variant::Int32(_) => DataTypeId::Int32,
            Variant::UInt32(_) => DataTypeId::UInt32,
            Variant::Double(_) => DataTypeId::Double,
            _ => DataTypeId::String,
        };
        let b = VariableBuilder::new(&self.id(path), self.name(ns, last), last)
            .data_type(data_type)
            .value(value);
        let b = if property {
            b.has_type_definition(VariableTypeId::PropertyType)
                .property_of(parent)
        } else {
            b.has_type_definition(VariableTypeId::BaseDataVariableType)
                .component_of(parent)
        };
        b.insert(space);
    }

    /// The variables' values, in [`VARIABLES`] order.
    fn values(v: &Values) -> Vec<Variant> {
        let texts = |f: fn(&model::AlarmView) -> String| -> Vec<String> {
            v.alarms.iter().map(f).collect()
        };
        vec![
            v.channel_state.into(),
            v.channel_mode.into(),
            v.feed_override.into(),
            v.feed_rate.into(),
            v.program_name.as_str().into(),
            v.program_path.as_str().into(),
            v.line.into(),
            v.block.as_str().into(),
            v.tool.into(),
            v.edge.into(),
            v.connected.into(),
            v.spindle_rotating.into(),
            v.spindle_setpoint.into(),
            v.spindle_actual.into(),
            v.program_name.as_str().into(),
            LocalizedText::new("", v.production_state).into(),
            (v.alarms.len() as u32).into(),
            v.alarms
                .iter()
                .map(|a| a.number)
                .collect::<Vec<u32>>()
                .into(),
            texts(|a| a.text.clone()).into(),
            texts(|a| a.program.clone()).into(),
            v.alarms.iter().map(|a| a.line).collect::<Vec<u32>>().into(),
        ]
    }

    /// Writes `v` into the variables; without a kernel the last values stay, marked
    /// uncertain.
    pub fn update(&self, v: &Values) {
        let status = if v.connected {
            StatusCode::Good
        } else {
            StatusCode::UncertainLastUsableValue
        };
        let now = DateTime::now();
        let ids: Vec<NodeId> = VARIABLES.iter().map(|x| self.id(x.0)).collect();
        let values = Self::values(v).into_iter().map(|value| DataValue {
            value: Some(value),
            status: Some(status),
            source_timestamp: Some(now),
            server_timestamp: Some(now),
            ..DataValue::default()
        });
        let items = ids.iter().zip(values).map(|(id, dv)| (id, None, dv));
        if let Err(e) = self.manager.set_values(&self.subscriptions, items) {
            eprintln!("opcua: cannot write the values: {e}");
        }
    }

    /// The Tools folder for the kernel's table: its entries' nodes made anew when the
    /// table's version changes.
    pub fn update_tools(&mut self, table: Option<&ToolTableMsg>) {
        let Some(table) = table else { return };
        if self.tools_version == Some(table.version) {
            return;
        }
        self.tools_version = Some(table.version);
        let mut space = self.manager.address_space().write();
        for id in self.tool_nodes.drain(..) {
            space.delete(&id, true);
        }
        for e in table.entries() {
            let name = model::tool_name(e);
            let path = format!("Equipment/Tools/{name}");
            let tool = self.id(&path);
            ObjectBuilder::new(&tool, self.name(Ns::Softnc, &name), name.as_str())
                .has_type_definition(ObjectTypeId::BaseObjectType)
                .organized_by(self.id("Equipment/Tools"))
                .insert(&mut *space);
            self.tool_nodes.push(tool.clone());
            let fields: [(&str, Ns, Variant); 7] = [
                ("ControlIdentifier1", Ns::MachineTool, e.t.into()),
                ("ControlIdentifier2", Ns::MachineTool, e.d.into()),
                ("Name", Ns::MachineTool, name.as_str().into()),
                ("Radius", Ns::Softnc, e.radius.into()),
                ("RadiusWear", Ns::Softnc, e.radius_wear.into()),
                ("Length", Ns::Softnc, e.length.into()),
                ("LengthWear", Ns::Softnc, e.length_wear.into()),
            ];
            for (field, ns, value) in fields {
                let field = format!("{path}/{field}");
                self.fixed(&mut space, &field, ns, value, false);
                self.tool_nodes.push(self.id(&field));
            }
        }
        drop(space);
        let version = self.id("Equipment/Tools/TableVersion");
        let dv = DataValue::new_now(Variant::from(table.version));
        if let Err(e) = self
            .manager
            .set_value(&self.subscriptions, &version, None, dv)
        {
            eprintln!("opcua: cannot write the tool table's version: {e}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{channel_state, production_state};
    use opcua::server::node_manager::memory::simple_node_manager_imports;
    use opcua::server::{ServerBuilder, ServerEndpoint, ANONYMOUS_USER_TOKEN_ID};
    use opcua::types::{AttributeId, DataEncoding, NumericRange, TimestampsToReturn};
    use softnc_protocol::ToolEntry;

    /// A built server (not listening) with the machine `mill` in it; its certificate
    /// folder is removed when the test ends.
    struct Fixture {
        space: Space,
        pki: std::path::PathBuf,
        // The server's sampler lives on it; never driven here.
        _rt: tokio::runtime::Runtime,
    }

    impl Drop for Fixture {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.pki);
        }
    }

    fn fixture(tag: &str) -> Fixture {
        let pki =
            std::env::temp_dir().join(format!("softnc-opcua-test-{tag}-{}", std::process::id()));
        let rt = tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap();
        let _inside = rt.enter();
        let (_server, handle) = ServerBuilder::new()
            .application_name("test")
            .pki_dir(&pki)
            .add_endpoint(
                "none",
                ServerEndpoint::new_none("/", &[ANONYMOUS_USER_TOKEN_ID.to_string()]),
            )
            .discovery_urls(vec!["/".into()])
            .with_node_manager(simple_node_manager_imports(
                vec![Box::new(Namespaces)],
                "softnc",
            ))
            .build()
            .unwrap();
        let manager = handle
            .node_managers()
            .get_of_type::<SimpleNodeManager>()
            .unwrap();
        let identity = Identity {
            model: "softnc test".into(),
            serial: "mill".into(),
        };
        let space = Space::new(manager, handle.subscriptions().clone(), "mill", &identity).unwrap();
        drop(_inside);
        Fixture {
            space,
            pki,
            _rt: rt,
        }
    }

    /// The node at `path` under the machine: its browse name and its value.
    fn read(s: &Space, path: &str) -> Option<(QualifiedName, DataValue)> {
        let space = s.manager.address_space().read();
        let node = space.find(&s.id(path))?;
        let value = node.as_node().get_attribute(
            TimestampsToReturn::Neither,
            AttributeId::Value,
            &NumericRange::None,
            &DataEncoding::Binary,
        )?;
        Some((node.as_node().browse_name().clone(), value))
    }

    fn running() -> Values {
        Values {
            connected: true,
            channel_state: channel_state::ACTIVE,
            channel_mode: 0,
            feed_override: 80.0,
            feed_rate: 1200.0,
            program_name: "part.mpf".into(),
            program_path: "/shop/part.mpf".into(),
            line: 7,
            block: "N70 X10".into(),
            production_state: production_state::RUNNING,
            spindle_setpoint: 1500.0,
            spindle_actual: 1498.0,
            spindle_rotating: true,
            tool: 1,
            edge: 2,
            alarms: vec![model::AlarmView {
                number: 14040,
                text: "program alarm".into(),
                program: "part.mpf".into(),
                line: 7,
            }],
        }
    }

    /// The variables carry the values under the specification's browse names in its
    /// namespace, softnc's own in softnc's; Identification is there from the start.
    #[test]
    fn the_channel_under_its_browse_names() {
        let f = fixture("names");
        let s = &f.space;
        f.space.update(&running());
        let (name, v) = read(s, "Monitoring/Channel_1/ChannelState").unwrap();
        assert_eq!(name, QualifiedName::new(s.mt, "ChannelState"));
        assert_eq!(v.value, Some(Variant::Int32(0)));
        assert_eq!(v.status, Some(StatusCode::Good));
        let (_, v) = read(s, "Monitoring/Channel_1/FeedOverride").unwrap();
        assert_eq!(v.value, Some(Variant::Double(80.0)));
        let (name, v) = read(s, "Monitoring/Channel_1/ProgramName").unwrap();
        assert_eq!(name, QualifiedName::new(s.own, "ProgramName"));
        assert_eq!(v.value, Some(Variant::from("part.mpf")));
        let (_, v) = read(s, "Production/ActiveProgram/State/CurrentState").unwrap();
        assert_eq!(v.value, Some(LocalizedText::new("", "Running").into()));
        let (_, v) = read(s, "Notification/Alarms/Numbers").unwrap();
        assert_eq!(v.value, Some(Variant::from(vec![14040u32])));
        let (name, v) = read(s, "Monitoring/MachineTool/OperationMode").unwrap();
        assert_eq!(name, QualifiedName::new(s.mt, "OperationMode"));
        assert_eq!(v.value, Some(Variant::Int32(1)));
        let (_, v) = read(s, "Monitoring/Channel_1/Name").unwrap();
        assert_eq!(v.value, Some(Variant::from("Channel 1")));
        let (name, v) = read(s, "Identification/SerialNumber").unwrap();
        assert_eq!(name, QualifiedName::new(s.mt, "SerialNumber"));
        assert_eq!(v.value, Some(Variant::from("mill")));
    }

    /// Every variable is read-only for every user: clients' writes are refused (docs/opcua.md,
    /// Access).
    #[test]
    fn every_variable_is_read_only() {
        use opcua::nodes::{AccessLevel, NodeType};
        let mut f = fixture("read-only");
        let table = ToolTableMsg {
            version: 1,
            count: 1,
            ..ToolTableMsg::default()
        };
        f.space.update_tools(Some(&table));
        let fixed = [
            "Identification/SerialNumber",
            "Monitoring/MachineTool/OperationMode",
            "Equipment/Tools/TableVersion",
            "Equipment/Tools/D0/Radius",
        ];
        let paths = VARIABLES.iter().map(|v| v.0).chain(fixed);
        let space = f.space.manager.address_space().read();
        for path in paths {
            let Some(NodeType::Variable(v)) = space.find(&f.space.id(path)) else {
                panic!("no variable {path}");
            };
            assert_eq!(
                v.access_level().bits(),
                AccessLevel::CURRENT_READ.bits(),
                "{path}"
            );
            let user = v.user_access_level().bits();
            assert_eq!(user, AccessLevel::CURRENT_READ.bits(), "{path}");
        }
    }

    /// Without a kernel the last values stay, uncertain.
    #[test]
    fn without_a_kernel_the_values_are_uncertain() {
        let f = fixture("uncertain");
        let mut v = running();
        v.connected = false;
        f.space.update(&v);
        let (_, dv) = read(&f.space, "Monitoring/Channel_1/ChannelState").unwrap();
        assert_eq!(dv.status, Some(StatusCode::UncertainLastUsableValue));
        assert_eq!(dv.value, Some(Variant::Int32(0)));
    }

    /// The tool list follows the table's version: two offsets, then one; the other's
    /// nodes go.
    #[test]
    fn the_tool_list_follows_the_table() {
        let mut f = fixture("tools");
        let mut table = ToolTableMsg {
            version: 1,
            count: 2,
            ..ToolTableMsg::default()
        };
        table.entries[0] = ToolEntry {
            t: 1,
            d: 2,
            radius: 0.4,
            ..ToolEntry::default()
        };
        table.entries[1] = ToolEntry {
            d: 3,
            radius: 5.0,
            length: 80.0,
            ..ToolEntry::default()
        };
        f.space.update_tools(Some(&table));
        let s = &f.space;
        let (_, v) = read(s, "Equipment/Tools/T1 D2/Radius").unwrap();
        assert_eq!(v.value, Some(Variant::Double(0.4)));
        let (name, v) = read(s, "Equipment/Tools/D3/ControlIdentifier2").unwrap();
        assert_eq!(name, QualifiedName::new(s.mt, "ControlIdentifier2"));
        assert_eq!(v.value, Some(Variant::UInt32(3)));
        table.version = 2;
        table.count = 1;
        f.space.update_tools(Some(&table));
        let s = &f.space;
        assert!(read(s, "Equipment/Tools/D3/Radius").is_none());
        let gone = s.id("Equipment/Tools/D3");
        assert!(s.manager.address_space().read().find(&gone).is_none());
        assert!(read(s, "Equipment/Tools/T1 D2/Radius").is_some());
        let (_, v) = read(s, "Equipment/Tools/TableVersion").unwrap();
        assert_eq!(v.value, Some(Variant::UInt32(2)));
    }
}
