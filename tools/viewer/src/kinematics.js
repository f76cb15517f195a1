// Forward kinematics of the robot description printed by scene_json: the URDF joint tree
// (origins, revolute axes) and base poses from roll, pitch, yaw. Plain three.js math, so the
// page and the node assembler (which checks it against rbcp::RobotModel) share one code path.
import { Euler, Matrix4, Quaternion, Vector3 } from 'three';

/** Rotation R = Rz(yaw) Ry(pitch) Rx(roll), the convention of the plans and traces. */
export function quaternionFromRpy([roll, pitch, yaw]) {
  return new Quaternion().setFromEuler(new Euler(roll, pitch, yaw, 'ZYX'));
}

/** 4x4 transform from {xyz, quaternion: [x, y, z, w]}. */
export function poseMatrix({ xyz, quaternion }) {
  return new Matrix4().compose(new Vector3(...xyz), new Quaternion(...quaternion), new Vector3(1, 1, 1));
}

/** World transform of the base from {position, rpy}. */
export function baseMatrix({ position, rpy }) {
  return new Matrix4().compose(new Vector3(...position), quaternionFromRpy(rpy), new Vector3(1, 1, 1));
}

/**
 * Pose of every link in the base frame for the joint vector q (12 angles, in the order of
 * robot.joint_order). Returns a Map from link name to Matrix4. Joints come in tree order
 * (scene_json lists them breadth first), so a parent link is always placed before its child.
 */
export function linkPoses(robot, q) {
  const index = new Map(robot.joint_order.map((name, i) => [name, i]));
  const poses = new Map([[robot.links[0].name, new Matrix4()]]);
  for (const joint of robot.joints) {
    const parent = poses.get(joint.parent);
    if (!parent) throw new Error(`joint ${joint.name}: parent link ${joint.parent} not placed yet`);
    const pose = parent.clone().multiply(poseMatrix(joint.origin));
    if (joint.type === 'revolute' || joint.type === 'continuous') {
      if (!index.has(joint.name)) throw new Error(`joint ${joint.name} is not in joint_order`);
      const angle = q[index.get(joint.name)];
      pose.multiply(new Matrix4().makeRotationAxis(new Vector3(...joint.axis).normalize(), angle));
    } else if (joint.type !== 'fixed') {
      throw new Error(`joint ${joint.name}: unsupported type ${joint.type}`);
    }
    poses.set(joint.child, pose);
  }
  return poses;
}

/**
 * Foot contact points in the frame of `poses`, {LF, RF, LH, RH}: the FOOT frame origin plus
 * foot_contact_offset, which anymal_b.yaml gives in the shank (KFE child) frame.
 */
export function footContacts(robot, poses) {
  const feet = {};
  for (const leg of ['LF', 'RF', 'LH', 'RH']) {
    const rotation = new Matrix4().extractRotation(poses.get(`${leg}_SHANK`));
    const offset = new Vector3(...robot.foot_contact_offset).applyMatrix4(rotation);
    feet[leg] = new Vector3().setFromMatrixPosition(poses.get(`${leg}_FOOT`)).add(offset);
  }
  return feet;
}

/** Hip (HAA joint origin) of each leg in the base frame, {LF, RF, LH, RH}. */
export function hipPositions(robot) {
  const hips = {};
  for (const leg of ['LF', 'RF', 'LH', 'RH']) {
    const joint = robot.joints.find((j) => j.name === `${leg}_HAA`);
    hips[leg] = new Vector3(...joint.origin.xyz);
  }
  return hips;
}
