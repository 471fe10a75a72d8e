//! Generates the ROS 1 message types from the `.msg` copies in `ros_msgs/`.

fn main() {
    let root = std::path::PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap()).join("ros_msgs");
    let (source, deps) = roslibrust_codegen::find_and_generate_ros_messages_without_ros_package_path(vec![root.clone()])
        .unwrap_or_else(|e| panic!("generating ROS messages from {}: {e}", root.display()));
    for d in deps {
        println!("cargo:rerun-if-changed={}", d.display());
    }
    println!("cargo:rerun-if-changed=build.rs");
    let out = std::path::PathBuf::from(std::env::var("OUT_DIR").unwrap()).join("ros_msgs.rs");
    std::fs::write(&out, source.to_string()).unwrap();
}
