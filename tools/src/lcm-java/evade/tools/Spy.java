// lcm-spy with the URL's recv_buf_size applied (see ReceiveBuffer).
//   java evade.tools.Spy --lcm-url URL
package evade.tools;

public final class Spy {
  private Spy() {}

  // A 30,000-point LIDAR_POINTS message (x, y, z, intensity, ring, time_offset).
  private static final int kOneCloudBytes = 30000 * 21;

  public static void main(String[] args) throws Exception {
    String url = null;
    for (int i = 0; i < args.length; ++i) {
      if (args[i].equals("--lcm-url") && i + 1 < args.length) url = args[++i];
      else if (args[i].startsWith("--lcm-url=")) url = args[i].substring("--lcm-url=".length());
    }
    lcm.spy.Spy spy = new lcm.spy.Spy(url);
    int wanted = url == null ? 0 : ReceiveBuffer.fromUrl(url);
    if (wanted <= 0) return;
    java.lang.reflect.Field f = lcm.spy.Spy.class.getDeclaredField("lcm");
    f.setAccessible(true);
    int granted = ReceiveBuffer.apply((lcm.lcm.LCM) f.get(spy), wanted);
    System.err.println("lcm-spy: receive buffer: asked " + wanted + " bytes, the kernel granted " + granted
        + " (the kernel caps the request at net.core.rmem_max)");
    if (granted < kOneCloudBytes) {
      System.err.println("lcm-spy: less than one point cloud (" + kOneCloudBytes + " bytes): LIDAR_POINTS will be"
          + " dropped; as root: sysctl -w net.core.rmem_max=" + wanted);
    }
  }
}
