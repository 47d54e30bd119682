// Java's LCM 1.3.1 ignores the URL's recv_buf_size: UDPMulticastProvider
// opens its MulticastSocket with the kernel's default receive buffer
// (net.core.rmem_default, 208 KB on Debian 12) and never sets SO_RCVBUF, and
// it reads no system property for it. A 480 KB point cloud arrives as about
// eight 64 KB fragments per message; at 10 Hz most are dropped before Java
// reads them. This sets SO_RCVBUF on the provider's socket after LCM has
// opened it (the field is package-private: reflection). The kernel caps the
// request at net.core.rmem_max; what it granted is returned. Measured by
// test_java_receive_buffer (30 clouds of 30,000 points at 10 Hz, in a
// network namespace): 0 heard without this, 30 with.
package evade.tools;

import java.lang.reflect.Field;
import java.net.MulticastSocket;
import java.util.List;

public final class ReceiveBuffer {
  private ReceiveBuffer() {}

  // Sets the receive buffer of every udpm provider of `lcm`; returns the
  // size the kernel reports for the last one, or -1 when there is none.
  public static int apply(lcm.lcm.LCM lcm, int bytes) throws Exception {
    Field providersField = lcm.lcm.LCM.class.getDeclaredField("providers");
    providersField.setAccessible(true);
    int granted = -1;
    for (Object provider : (List<?>) providersField.get(lcm)) {
      if (!(provider instanceof lcm.lcm.UDPMulticastProvider)) continue;
      Field sockField = lcm.lcm.UDPMulticastProvider.class.getDeclaredField("sock");
      sockField.setAccessible(true);
      MulticastSocket sock = (MulticastSocket) sockField.get(provider);
      sock.setReceiveBufferSize(bytes);
      granted = sock.getReceiveBufferSize();
    }
    return granted;
  }

  // recv_buf_size=N from an LCM URL, or 0 when it has none.
  public static int fromUrl(String url) {
    int q = url.indexOf('?');
    if (q < 0) return 0;
    for (String kv : url.substring(q + 1).split("&")) {
      String[] p = kv.split("=", 2);
      if (p.length == 2 && p[0].equals("recv_buf_size")) return Integer.parseInt(p[1]);
    }
    return 0;
  }
}
