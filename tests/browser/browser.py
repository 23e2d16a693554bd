"""Headless Chromium for pkmkit's HTML views (Debian chromium, chromium-driver, python3-selenium):
a browser that starts clean (fresh profile, no background traffic), loads a page from a file,
and tells what the page logged and every request it made."""

import io
import json
import os
import shutil
import tempfile

from PIL import Image
from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.support.ui import WebDriverWait


class Browser:
    def __init__(self, width=1400, height=1500):
        self.profile = tempfile.mkdtemp(prefix="pkm-chromium-")
        options = webdriver.ChromeOptions()
        options.binary_location = "/usr/bin/chromium"
        for argument in ["--headless=new", "--no-sandbox", "--disable-gpu",
                         "--disable-dev-shm-usage", "--disable-background-networking",
                         "--disable-component-update", "--disable-sync", "--no-first-run",
                         "--disable-default-apps", "--disable-extensions",
                         "--hide-scrollbars", "--force-device-scale-factor=1",
                         f"--window-size={width},{height}",
                         f"--user-data-dir={self.profile}"]:
            options.add_argument(argument)
        options.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
        self.driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)

    def close(self):
        try:
            self.driver.quit()
        finally:
            shutil.rmtree(self.profile, ignore_errors=True)

    def load(self, path, timeout_s=30):
        """Loads the page; returns its URL once the view says it is ready."""
        self.driver.get_log("browser")  # drop what earlier pages logged
        self.driver.get_log("performance")
        url = "file://" + os.path.abspath(path)
        self.driver.get(url)
        WebDriverWait(self.driver, timeout_s).until(
            lambda d: d.execute_script("return !!(window.pkmView && window.pkmView.ready)"))
        return url

    def console_errors(self):
        return [entry for entry in self.driver.get_log("browser")
                if entry["level"] in ("SEVERE", "WARNING")]

    def requests(self):
        """Every URL the page asked for since it was loaded (DevTools' Network events)."""
        urls = []
        for entry in self.driver.get_log("performance"):
            message = json.loads(entry["message"])["message"]
            if message["method"] != "Network.requestWillBeSent":
                continue
            # The browser's own new-tab page (chrome://) may still be loading at start.
            document = message["params"].get("documentURL", "")
            url = message["params"]["request"]["url"]
            if not document.startswith("chrome://") and not url.startswith("chrome://"):
                urls.append(url)
        return urls

    def element_image(self, css):
        element = self.driver.find_element("css selector", css)
        return Image.open(io.BytesIO(element.screenshot_as_png)).convert("RGB")

    def script(self, text, *arguments):
        return self.driver.execute_script(text, *arguments)


def non_background_fraction(image, background=(255, 255, 255)):
    """The fraction of pixels that differ from the background colour."""
    pixels = image.getdata()
    differing = sum(1 for p in pixels if max(abs(p[k] - background[k]) for k in range(3)) > 8)
    return differing / max(1, len(pixels))


def distinct_colours(image):
    return len(set(image.getdata()))


def changed_pixels(a, b):
    """Pixels that differ between two images of the same size."""
    return sum(1 for p, q in zip(a.getdata(), b.getdata())
               if max(abs(p[k] - q[k]) for k in range(3)) > 24)
